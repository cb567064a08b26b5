#include "bus/process/faults.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdlib>
#include <sstream>
#include <string>

namespace mtg::process {

int fault_setting(std::string_view name) {
  const char* env = std::getenv("MTG_FAULTS");
  if (env == nullptr) return -1;
  std::stringstream in(env);
  std::string item;
  int value = -1;
  while (std::getline(in, item, ',')) {
    const auto colon = item.find(':');
    if (colon != std::string::npos && std::string_view(item).substr(0, colon) == name) {
      value = std::atoi(item.c_str() + colon + 1);
    }
  }
  return value;
}

bool first_time_fault(std::string_view mark) {
  const char* dir = std::getenv("MTG_FAULT_MARKS");
  if (dir == nullptr || *dir == '\0') return false;
  const std::string file = std::string(dir) + "/" + std::string(mark);
  const int fd = ::open(file.c_str(), O_CREAT | O_EXCL | O_WRONLY | O_CLOEXEC, 0600);
  if (fd < 0) return false;  // taken before (or the folder is not there: no fault)
  ::close(fd);
  return true;
}

}  // namespace mtg::process
