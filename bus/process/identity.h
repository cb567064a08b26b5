#pragma once
// How a process names itself on the bus.

#include <string>

namespace mtg::process {

/// This machine's host name ("unknown" if it has none).
std::string host_name();

/// "<role>:<host>:<pid>", unique per process.
std::string sender_id(const std::string& role);

}  // namespace mtg::process
