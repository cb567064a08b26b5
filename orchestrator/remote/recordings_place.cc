#include "orchestrator/remote/recordings_place.h"

#include "core/util/error.h"

namespace mtg::orchestrator::remote {

std::string RecordingsPlace::to_string() const {
  switch (kind) {
    case Kind::kCoordinator: return "coordinator";
    case Kind::kShared: return "shared:" + folder.string();
    case Kind::kWorker: return "worker";
  }
  return "coordinator";
}

RecordingsPlace parse_recordings_place(const std::string& text) {
  RecordingsPlace p;
  if (text.empty() || text == "coordinator") return p;
  if (text == "worker") {
    p.kind = RecordingsPlace::Kind::kWorker;
    return p;
  }
  const std::string prefix = "shared:";
  if (text.rfind(prefix, 0) == 0 && text.size() > prefix.size()) {
    p.kind = RecordingsPlace::Kind::kShared;
    p.folder = std::filesystem::absolute(text.substr(prefix.size())).lexically_normal();
    return p;
  }
  throw Error("--recordings '" + text + "': say coordinator (sent to the coordinator, the default), shared:PATH (a "
              "folder every host sees at PATH) or worker (kept on each worker; `mtg gather` brings them in)");
}

}  // namespace mtg::orchestrator::remote
