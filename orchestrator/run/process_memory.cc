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

// The fields of /proc/<pid>/stat after the parenthesised name (which may itself hold spaces and
// parentheses): the state is [0], so field k of proc(5) is [k - 3]. Empty when the process is gone.
std::vector<std::string> stat_fields(const std::string& file) {
  std::ifstream in(file);
  std::string stat((std::istreambuf_iterator<char>(in)), {});
  const auto close = stat.rfind(')');
  if (close == std::string::npos) return {};
  std::istringstream rest(stat.substr(close + 1));
  std::vector<std::string> out;
  for (std::string field; rest >> field;) out.push_back(field);
  return out;
}

std::vector<std::string> stat_fields(pid_t pid) { return stat_fields("/proc/" + std::to_string(pid) + "/stat"); }

double cpu_seconds_of(const std::vector<std::string>& f) {
  return (std::stod(f[11]) + std::stod(f[12])) / static_cast<double>(::sysconf(_SC_CLK_TCK));  // utime, stime
}

pid_t parent_of(pid_t pid) {
  const auto f = stat_fields(pid);
  return f.size() > 1 ? static_cast<pid_t>(std::stol(f[1])) : 0;
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

double process_cpu_seconds(pid_t pid) {
  const auto f = stat_fields(pid);
  if (f.size() < 13) return 0.0;
  return cpu_seconds_of(f);
}

std::optional<ThreadActivity> main_thread_activity(pid_t pid) {
  const std::string id = std::to_string(pid);
  const auto f = stat_fields("/proc/" + id + "/task/" + id + "/stat");
  if (f.size() < 13 || f[0].empty()) return std::nullopt;
  return ThreadActivity{f[0][0], cpu_seconds_of(f)};
}

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
    out.push_back({pid, pid == root ? "mtg" : role_of(pid), rss, process_cpu_seconds(pid)});
  }
  return out;
}

}  // namespace mtg::orchestrator
