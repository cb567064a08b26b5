#include "agents/vlm/secrets.h"

#include <cstdlib>
#include <sstream>

#include "core/util/error.h"
#include "core/util/text.h"

namespace mtg::vlm {
namespace {

std::string key_from_file(const std::string& file, const std::string& variable) {
  const std::string text = read_text_file(file, "key file");
  if (text.find('=') == std::string::npos) return trim_whitespace(text);
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    std::string name = trim_whitespace(line.substr(0, eq));
    if (name.rfind("export ", 0) == 0) name = trim_whitespace(name.substr(7));
    if (name == variable) return trim_whitespace(line.substr(eq + 1));
  }
  throw Error(file + ": no line " + variable + "=... in the key file");
}

}  // namespace

std::string ApiKey::redact(std::string_view text) const {
  std::string out(text);
  if (value_.size() < 4) return out;  // too short to tell from ordinary text
  for (auto pos = out.find(value_); pos != std::string::npos; pos = out.find(value_, pos)) {
    out.replace(pos, value_.size(), "[redacted]");
  }
  return out;
}

ApiKey load_api_key(const ModelSpec& spec, const std::string& key_file) {
  const std::string variable = api_key_variable(spec.provider);
  std::string key;
  if (!key_file.empty()) {
    key = key_from_file(key_file, variable);
  } else if (const char* v = std::getenv(variable.c_str()); v != nullptr) {
    key = trim_whitespace(v);
  }
  if (key.empty() && spec.provider != Provider::kOpenAiCompatible) {
    throw Error(key_file.empty() ? variable + " is not set (export it, or give a key file with --key-file)"
                                 : key_file + ": the key file is empty");
  }
  return ApiKey(key);
}

}  // namespace mtg::vlm
