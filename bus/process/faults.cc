#include "bus/process/faults.h"

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

}  // namespace mtg::process
