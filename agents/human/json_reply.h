#pragma once
// JSON answers of the local pages' HTTP APIs (the viewer, the play page, the audit): a body and
// its status, and a mistake as one line, {"error": "..."}.

#include <httplib.h>

#include <nlohmann/json.hpp>
#include <string>

namespace mtg::web {

inline void send_json(httplib::Response& res, const nlohmann::json& body, int status = 200) {
  res.status = status;
  // A model reply need not be valid UTF-8: shown with U+FFFD rather than a failed page.
  res.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), "application/json");
}

inline void send_error(httplib::Response& res, int status, const std::string& message) {
  send_json(res, {{"error", message}}, status);
}

}  // namespace mtg::web
