#include "core/util/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>

#include "core/util/error.h"
#include "core/util/host_name.h"

namespace mtg {
namespace fs = std::filesystem;
namespace {

// Whether process `pid` of this host still runs (EPERM: it does, as another user's).
bool process_alive(long pid) { return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM; }

// The pid a partial name of this host ends with, or -1 when `name` is none of this host's.
long partial_pid(const std::string& name, const std::string& prefix) {
  if (name.compare(0, prefix.size(), prefix) != 0) return -1;
  const std::string digits = name.substr(prefix.size());
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stol(digits);
}

// Partials of `target` left by writers of this host that are gone (and the `.partial` of
// versions before per-writer names), with their SQLite journals.
void remove_stale_partials(const fs::path& target) {
  const std::string base = target.filename().string();
  const std::string prefix = base + ".partial-" + host_name() + "-";
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    const long pid = partial_pid(name, prefix);
    const bool stale = name == base + ".partial" || (pid > 0 && !process_alive(pid));
    if (!stale) continue;
    fs::remove(e.path(), ec);
    fs::remove(e.path().string() + "-journal", ec);
  }
}

}  // namespace

void require_replaceable(const fs::path& target) {
  // A rename replaces whatever the name holds: as root, `--out /dev/null` would leave a regular
  // file where the device was and break the machine. Only a regular file (or nothing) is
  // replaced; a link is followed to what it names.
  std::error_code ec;
  const fs::file_status st = fs::status(target, ec);
  if (ec || !fs::exists(st) || fs::is_regular_file(st)) return;
  const char* what = fs::is_directory(st)        ? "a folder"
                     : fs::is_character_file(st) ? "a character device"
                     : fs::is_block_file(st)     ? "a block device"
                     : fs::is_fifo(st)           ? "a FIFO"
                     : fs::is_socket(st)         ? "a socket"
                                                 : "not a regular file";
  throw Error(target.string() + ": is " + what + "; give the path of a file to write");
}

void require_plain_file(const fs::path& target) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(target, ec);
  if (ec || !fs::exists(st) || fs::is_regular_file(st)) return;
  if (fs::is_symlink(st)) {
    throw Error(target.string() + ": is a symbolic link; refusing to write through it (remove it, or give another path)");
  }
  require_replaceable(target);  // names what else it is
  throw Error(target.string() + ": is not a regular file; give the path of a file to write");
}

int open_plain_file(const fs::path& file, int flags, unsigned mode) {
  require_plain_file(file);
  // O_NOFOLLOW closes the gap between the check and the open: a link made meanwhile fails it.
  const int fd = ::open(file.c_str(), flags | O_NOFOLLOW | O_CLOEXEC, static_cast<mode_t>(mode));
  if (fd < 0) {
    const int error = errno;
    if (error == ELOOP) throw Error(file.string() + ": is a symbolic link; refusing to write through it");
    throw Error(file.string() + ": cannot open (" + std::strerror(error) + ")");
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw Error(file.string() + ": is not a regular file; give the path of a file to write");
  }
  return fd;
}

PartialFile::PartialFile(fs::path target, Stale stale) : target_(std::move(target)) {
  require_replaceable(target_);
  if (stale == Stale::kRemove) remove_stale_partials(target_);
  path_ = target_.string() + ".partial-" + host_name() + "-" + std::to_string(::getpid());
  const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw Error(target_.string() + ": cannot create " + path_.filename().string() + " (" + std::strerror(errno) +
                (errno == EEXIST ? "; this process is writing it already)" : ")"));
  }
  ::close(fd);
}

PartialFile::~PartialFile() {
  if (committed_) return;
  std::error_code ignored;
  fs::remove(path_, ignored);
  fs::remove(path_.string() + "-journal", ignored);
}

void PartialFile::commit() {
  require_replaceable(target_);  // it may have been made since the writer began
  std::error_code ec;
  fs::rename(path_, target_, ec);
  if (ec) throw Error(target_.string() + ": cannot move the finished file into place (" + ec.message() + ")");
  committed_ = true;
}

void write_file_atomically(const fs::path& file, const std::function<void(std::ostream&)>& write) {
  PartialFile partial(file);
  {
    std::ofstream out(partial.path(), std::ios::binary | std::ios::trunc);
    if (!out) throw Error(file.string() + ": cannot write");
    write(out);
    if (!out) throw Error(file.string() + ": write failed");
  }
  partial.commit();
}

}  // namespace mtg
