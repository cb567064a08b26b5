#pragma once
// `mtg audit`: a person judges sampled tasks from exactly what the agent sees (docs/view.md,
// "mtg audit"); `mtg audit report`: the paper's Table 2 from the answers.

#include <cstdint>
#include <string>

namespace mtg::cli {

struct AuditCommandOptions {
  std::string tasks;
  std::string scene;
  int per_level = 10;
  std::uint64_t seed = 0;
  std::string out;
  std::string data_dir;
  std::string profile = "replica_cad";
  int width = 640;
  int height = 480;
  bool names = false;
  std::string lookalike_aid = "both";
  std::string host = "127.0.0.1";
  int port = 8790;          // 0 = any free port
  bool prepare_only = false;  // make the folder, do not serve
  std::string rater = "rater";  // whose answers the page shows and stores (several people, one draw)
};

struct AuditReportOptions {
  std::string dir;
  bool json = false;
};

int run_audit(const AuditCommandOptions& options);
int run_audit_report(const AuditReportOptions& options);

}  // namespace mtg::cli
