#include "orchestrator/run/provenance.h"

#include <chrono>
#include <ctime>
#include <fcntl.h>
#include <unistd.h>

#include <fstream>

#include "core/tasks/task_db.h"
#include "core/util/atomic_file.h"
#include "core/util/build_info.h"
#include "core/util/error.h"
#include "core/util/host_name.h"

namespace mtg::orchestrator {

namespace fs = std::filesystem;

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

nlohmann::json make_provenance(const ProvenanceInputs& in) {
  nlohmann::json p;
  p["mtg_version"] = mtg_version();
  p["git_revision"] = mtg_git_revision();
  p["command"] = in.command;
  p["host"] = host_name();
  p["planned_at"] = utc_now();
  std::error_code ec;
  const auto bytes = fs::file_size(in.tasks_db, ec);
  p["task_set"] = {{"file", fs::absolute(in.tasks_db).string()},
                   {"config_hash", tasks::read_task_set_meta(in.tasks_db, "config_hash").value_or("unknown")},
                   {"bytes", ec ? nlohmann::json(nullptr) : nlohmann::json(bytes)}};
  p["dataset"] = nlohmann::json::object();
  for (const auto& [scene, f] : in.dataset) p["dataset"][scene] = f.digest();
  p["model_settings"] = in.model_settings;
  return p;
}

std::string task_set_identity(const nlohmann::json& p) {
  if (!p.is_object() || !p.contains("task_set")) return "";
  // Not the file's path: the same task set copied to another folder or host is the same set.
  std::string id = "config " + p["task_set"].value("config_hash", std::string("?"));
  if (p.contains("dataset") && p["dataset"].is_object()) {
    for (const auto& [scene, digest] : p["dataset"].items()) id += ", " + scene + " " + digest.get<std::string>();
  }
  return id;
}

void append_session(const fs::path& run_dir, const nlohmann::json& entry) {
  const fs::path file = run_dir / "sessions.jsonl";
  const int fd = open_plain_file(file, O_WRONLY | O_CREAT | O_APPEND);  // never through a planted link
  const std::string line = entry.dump() + '\n';
  const bool written = ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size());
  ::close(fd);
  if (!written) throw Error("cannot write " + file.string());
}

nlohmann::json read_sessions(const fs::path& run_dir) {
  nlohmann::json all = nlohmann::json::array();
  std::ifstream in(run_dir / "sessions.jsonl");
  std::string line;
  while (std::getline(in, line)) {
    nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_object()) all.push_back(std::move(j));
  }
  return all;
}

}  // namespace mtg::orchestrator
