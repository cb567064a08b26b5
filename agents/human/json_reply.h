#pragma once
// JSON answers of the local pages' HTTP APIs (the viewer, the play page, the audit): a body and
// its status, and a mistake as one line, {"error": "..."}.

#include <httplib.h>

#include <nlohmann/json.hpp>
#include <string>

namespace mtg::web {

inline void send_json(httplib::Response& res, const nlohmann::json& body, int status = 200) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

inline void send_error(httplib::Response& res, int status, const std::string& message) {
  send_json(res, {{"error", message}}, status);
}

}  // namespace mtg::web
