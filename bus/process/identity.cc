#include "bus/process/identity.h"

#include <unistd.h>

namespace mtg::process {

std::string sender_id(const std::string& role) {
  return role + ":" + host_name() + ":" + std::to_string(::getpid());
}

}  // namespace mtg::process
