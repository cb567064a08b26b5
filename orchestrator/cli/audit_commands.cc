#include "orchestrator/cli/audit_commands.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "core/util/error.h"
#include "orchestrator/audit/audit_builder.h"
#include "orchestrator/audit/audit_report.h"
#include "orchestrator/audit/audit_server.h"
#include "orchestrator/cli/serve_until_stopped.h"

namespace mtg::cli {

int run_audit(const AuditCommandOptions& o) {
  if (o.port < 0 || o.port > 65535) throw Error("--port must be 0..65535, not " + std::to_string(o.port));
  orchestrator::audit::AuditOptions a;
  a.tasks = o.tasks;
  a.scene = o.scene;
  a.per_level = o.per_level;
  a.seed = o.seed;
  a.out = o.out;
  a.data_dir = o.data_dir;
  a.profile = o.profile;
  a.width = o.width;
  a.height = o.height;
  a.names = o.names;
  a.lookalike_aid = o.lookalike_aid;
  const int n = orchestrator::audit::build_audit(a, std::cerr, ::isatty(STDERR_FILENO) != 0);
  if (o.prepare_only) {
    std::printf("audit of %d tasks in %s (serve it with the same command without --prepare-only)\n", n, o.out.c_str());
    return 0;
  }
  orchestrator::audit::AuditServer server(o.out, o.rater);
  server.bind(o.host, o.port);
  std::printf("auditing %d tasks at %s as %s; answers go to %s/audit.sqlite (Ctrl-C stops; the same command "
              "goes on where you left off; mtg audit report %s prints the table)\n",
              n, server.url().c_str(), o.rater.c_str(), o.out.c_str(), o.out.c_str());
  std::fflush(stdout);
  serve_until_stopped(server);
  return 0;
}

int run_audit_report(const AuditReportOptions& o) {
  if (!std::filesystem::exists(std::filesystem::path(o.dir) / "audit.sqlite")) {
    throw Error("mtg audit report: " + o.dir + " holds no audit (no audit.sqlite)");
  }
  orchestrator::audit::AuditStore store(o.dir, false);
  const auto report = orchestrator::audit::make_report(store.items(), store.all_answers());
  if (o.json) {
    std::printf("%s\n", report.to_json().dump(1).c_str());
  } else {
    std::printf("%s", report.to_text().c_str());
  }
  return 0;
}

}  // namespace mtg::cli
