#include "bus/process/subprocess.h"

#include <fcntl.h>
#include <sys/prctl.h>
#include <unistd.h>

#include "core/util/error.h"

namespace mtg::process {

pid_t spawn_process(const std::vector<std::string>& argv, const std::string& log_file, int parent_death_signal) {
  if (argv.empty()) throw Error("spawn_process: no program given");
  // Everything the child needs is prepared before fork: after it only async-signal-safe calls.
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw Error("cannot start " + argv[0] + ": fork failed");
  if (pid == 0) {
    ::prctl(PR_SET_PDEATHSIG, parent_death_signal);
    if (::getppid() != parent) ::_exit(1);  // the parent died before prctl took effect
    if (!log_file.empty()) {
      const int fd = ::open(log_file.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      if (fd >= 0) {
        ::dup2(fd, 1);
        ::dup2(fd, 2);
        ::close(fd);
      }
    }
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  return pid;
}

}  // namespace mtg::process
