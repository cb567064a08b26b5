#pragma once

#include <string>

namespace mtg {

/// This machine's host name ("unknown" if it has none).
std::string host_name();

}  // namespace mtg
