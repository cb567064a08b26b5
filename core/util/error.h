#pragma once
// Errors: mtg::Error is bad input (a file, field or message at fault) that a caller reports in
// one line; MTG_DEMAND guards our own invariants and names the source line when it fails.

#include <stdexcept>
#include <string>

namespace mtg {

/// Bad input. The message is one line that names the file, field or message at fault.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A broken invariant inside this code base (a bug, not bad input).
class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

[[noreturn]] void throw_internal_error(const char* condition, const char* file, int line,
                                       const std::string& detail);

}  // namespace mtg

#define MTG_DEMAND(cond, detail)                                         \
  do {                                                                   \
    if (!(cond)) ::mtg::throw_internal_error(#cond, __FILE__, __LINE__, (detail)); \
  } while (false)
