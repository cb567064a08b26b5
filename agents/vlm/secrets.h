#pragma once
// API keys: read from the provider's environment variable or a key file, never from the command
// line (argv is visible to every user and lands in the run's logs). The key lives only in the
// adapter's memory and in the request headers; every text that leaves the adapter (logs, bus
// messages, error replies) goes through redact() first, in case a server echoes it back.

#include <string>
#include <string_view>

#include "agents/vlm/model_spec.h"

namespace mtg::vlm {

class ApiKey {
 public:
  ApiKey() = default;
  explicit ApiKey(std::string value) : value_(std::move(value)) {}
  bool empty() const { return value_.empty(); }
  /// Only for building request headers.
  const std::string& reveal() const { return value_; }
  /// `text` with every occurrence of the key replaced by "[redacted]".
  std::string redact(std::string_view text) const;

 private:
  std::string value_;
};

/// The key for `spec`: from `key_file` when given (either the bare key, or lines NAME=value where
/// NAME is the provider's variable), else from the environment. openai-compatible servers may
/// need none. @throws mtg::Error naming the variable or file (never the key) when it is missing.
ApiKey load_api_key(const ModelSpec& spec, const std::string& key_file);

}  // namespace mtg::vlm
