#include "agents/vlm/secrets.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/util/error.h"

namespace mtg::vlm {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::string key_from_file(const std::string& file, const std::string& variable) {
  std::ifstream in(file);
  if (!in) throw Error(file + ": cannot read the key file");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  if (text.find('=') == std::string::npos) return trim(text);
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    std::string name = trim(line.substr(0, eq));
    if (name.rfind("export ", 0) == 0) name = trim(name.substr(7));
    if (name == variable) return trim(line.substr(eq + 1));
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
    key = trim(v);
  }
  if (key.empty() && spec.provider != Provider::kOpenAiCompatible) {
    throw Error(key_file.empty() ? variable + " is not set (export it, or give a key file with --key-file)"
                                 : key_file + ": the key file is empty");
  }
  return ApiKey(key);
}

}  // namespace mtg::vlm
