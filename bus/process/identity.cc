#include "bus/process/identity.h"

#include <unistd.h>

namespace mtg::process {

std::string host_name() {
  char buf[256] = {0};
  if (gethostname(buf, sizeof(buf) - 1) != 0) return "unknown";
  return buf;
}

std::string sender_id(const std::string& role) {
  return role + ":" + host_name() + ":" + std::to_string(::getpid());
}

}  // namespace mtg::process
