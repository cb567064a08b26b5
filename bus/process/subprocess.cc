#include "bus/process/subprocess.h"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>

#include "bus/private_network.h"
#include "core/util/error.h"

namespace mtg::process {
namespace {

// execv's argument vector over `argv`'s strings (which must outlive it).
std::vector<char*> c_argv(const std::vector<std::string>& argv) {
  if (argv.empty()) throw Error("no program given to start");
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  return args;
}

}  // namespace

pid_t spawn_process(const std::vector<std::string>& argv, const std::string& log_file, int parent_death_signal,
                    const bus::PrivateNetwork* network) {
  // Everything the child needs is prepared before fork: after it only async-signal-safe calls.
  std::vector<char*> args = c_argv(argv);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw Error("cannot start " + argv[0] + ": fork failed");
  if (pid == 0) {
    ::prctl(PR_SET_PDEATHSIG, parent_death_signal);
    if (::getppid() != parent) ::_exit(1);  // the parent died before prctl took effect
    if (!log_file.empty()) {
      // Not through a link planted at the log's name (the parent checked the folder before).
      const int fd = ::open(log_file.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_NOFOLLOW, 0644);
      if (fd >= 0) {
        ::dup2(fd, 1);
        ::dup2(fd, 2);
        ::close(fd);
      }
    }
    if (network != nullptr && !network->enter()) {
      static const char kWhy[] = "cannot enter the host bus's network namespace\n";
      (void)!::write(2, kWhy, sizeof kWhy - 1);
      ::_exit(127);
    }
    // Nothing of the parent but stdio goes on (after entering: the namespace is one of these):
    // liblcm's sockets are not close-on-exec, and a process in a private network must hold no
    // socket of the host's, such as its parent's shared bus.
    if (::close_range(3, ~0U, 0) != 0) {
      for (int fd = 3; fd < 4096; ++fd) ::close(fd);
    }
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  return pid;
}

void exec_process(const std::vector<std::string>& argv) {
  std::vector<char*> args = c_argv(argv);
  ::execv(args[0], args.data());
  throw Error("cannot start " + argv[0]);
}

CommandOutput run_command(const std::vector<std::string>& argv) {
  std::vector<char*> args = c_argv(argv);
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) throw Error("cannot run " + argv[0] + ": pipe failed");
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
    throw Error("cannot run " + argv[0] + ": fork failed");
  }
  if (pid == 0) {
    ::dup2(pipe_fds[1], 1);
    ::dup2(pipe_fds[1], 2);
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  ::close(pipe_fds[1]);
  CommandOutput out;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(pipe_fds[0], buffer, sizeof buffer);
    if (n > 0) {
      out.output.append(buffer, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(pipe_fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  out.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

}  // namespace mtg::process
