#include "orchestrator/run/run_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/host_name.h"

namespace mtg::orchestrator {

namespace {

std::string read_holder(int fd) {
  char buffer[256] = {};
  const ssize_t n = ::pread(fd, buffer, sizeof buffer - 1, 0);
  std::string holder(buffer, n > 0 ? static_cast<std::size_t>(n) : 0);
  while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) holder.pop_back();
  return holder.empty() ? "another process" : holder;
}

}  // namespace

RunLock::RunLock(const std::filesystem::path& dir, const std::string& what) {
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / ".lock";
  // Close-on-exec: the run's services must not keep the lock after the run itself is gone. Not
  // through a link: in a shared folder anyone may plant one at .lock, and the holder's line
  // would be written into whatever it names (issue 55).
  fd_ = open_plain_file(file, O_RDWR | O_CREAT);
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    const std::string holder = error == EWOULDBLOCK ? read_holder(fd_) : std::string();
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK) {
      throw Error(dir.string() + " is in use by " + holder +
                  "; wait for it to end (or stop it), or give another --out");
    }
    throw Error(file.string() + ": cannot lock the run folder (" + std::strerror(error) + ")");
  }
  const std::string holder = what + " (process " + std::to_string(::getpid()) + " on " + host_name() + ")\n";
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, holder.data(), holder.size(), 0) != static_cast<ssize_t>(holder.size())) {
    // The lock holds without the note; the refusal then says "another process".
  }
}

RunLock::~RunLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock; the file stays, naming the last holder
}

bool run_in_progress(const std::filesystem::path& dir) {
  const int fd = ::open((dir / ".lock").c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) return false;
  const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);  // a shared lock taken here goes with it
  return held;
}

}  // namespace mtg::orchestrator
