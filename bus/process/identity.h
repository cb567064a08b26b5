#pragma once
// How a process names itself on the bus.

#include <string>

#include "core/util/host_name.h"

namespace mtg::process {

using mtg::host_name;

/// "<role>:<host>:<pid>", unique per process.
std::string sender_id(const std::string& role);

}  // namespace mtg::process
