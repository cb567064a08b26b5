#include "orchestrator/run/process_memory.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <unistd.h>

namespace mtg::orchestrator {
namespace {

namespace fs = std::filesystem;

// The parent of `pid` from /proc/<pid>/stat (its fourth field, after the parenthesised name,
// which may itself hold spaces and parentheses); 0 when the process is gone.
pid_t parent_of(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), {});
  const auto close = stat.rfind(')');
  if (close == std::string::npos) return 0;
  std::istringstream rest(stat.substr(close + 1));
  std::string state;
  pid_t ppid = 0;
  rest >> state >> ppid;
  return ppid;
}

// utime + stime (fields 14 and 15 of /proc/<pid>/stat) in seconds; 0 when the process is gone.
double cpu_seconds_of(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), {});
  const auto close = stat.rfind(')');
  if (close == std::string::npos) return 0.0;
  std::istringstream rest(stat.substr(close + 2));
  std::string field;
  double ticks = 0.0;
  for (int i = 3; i <= 15 && rest >> field; ++i) {
    if (i == 14 || i == 15) ticks += std::stod(field);
  }
  return ticks / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

double rss_mib(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // "VmRSS:   1234 kB"
  }
  return -1.0;
}

std::string role_of(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/cmdline", std::ios::binary);
  std::vector<std::string> argv;
  for (std::string arg; std::getline(in, arg, '\0');) argv.push_back(arg);
  if (argv.empty()) return "?";
  std::string name = fs::path(argv[0]).filename().string();
  if (name.rfind("mtg_", 0) == 0) name = name.substr(4);
  if (name == "agent" || name == "vlm_agent") {
    const auto spec = std::find(argv.begin(), argv.end(), "--agent");
    if (spec != argv.end() && spec + 1 != argv.end()) name = "agent:" + *(spec + 1);
  }
  return name;
}

}  // namespace

std::vector<ProcessMemory> process_tree_memory(pid_t root) {
  std::map<pid_t, pid_t> parents;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || !std::all_of(name.begin(), name.end(), ::isdigit)) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(name));
    if (const pid_t ppid = parent_of(pid); ppid > 0) parents[pid] = ppid;
  }
  std::vector<ProcessMemory> out;
  for (const auto& [pid, ppid] : parents) {
    bool below = pid == root;
    for (pid_t p = ppid; !below && p > 0;) {
      below = p == root;
      const auto it = parents.find(p);
      p = it == parents.end() ? 0 : it->second;
    }
    if (!below) continue;
    const double rss = rss_mib(pid);
    if (rss < 0.0) continue;  // gone meanwhile
    out.push_back({pid, pid == root ? "mtg" : role_of(pid), rss, cpu_seconds_of(pid)});
  }
  return out;
}

}  // namespace mtg::orchestrator
