#include "core/util/json_file.h"

#include <fstream>
#include <sstream>

#include "core/util/atomic_file.h"
#include "core/util/error.h"

namespace mtg {
namespace {

std::string line_column(const std::string& text, std::size_t byte) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

std::string type_name(const nlohmann::json& v) { return v.type_name(); }

}  // namespace

nlohmann::json read_json_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": cannot open file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    std::string what = e.what();
    // nlohmann prefixes "[json.exception.parse_error.101] parse error at line..": keep the tail.
    if (const auto pos = what.find(": syntax error"); pos != std::string::npos) {
      what = "syntax error" + what.substr(pos + 14);
    }
    throw Error(file.string() + ": invalid JSON at " + line_column(text, e.byte) + ": " + what);
  } catch (const nlohmann::json::exception& e) {
    // A number too large for a double ("out_of_range.406"), found by scripts/fuzz: not a
    // parse_error, so it went past the catch above and ended the program.
    throw Error(file.string() + ": invalid JSON: " + e.what());
  }
}

void write_json_file(const std::filesystem::path& file, const nlohmann::json& value) {
  write_file_atomically(file, [&](std::ostream& out) { out << value.dump(1, ' ') << '\n'; });
}

JsonField JsonField::at(const std::string& key) const {
  if (!value_->is_object()) fail("expected an object, got " + type_name(*value_));
  const auto it = value_->find(key);
  if (it == value_->end()) fail("missing field '" + key + "'");
  return JsonField(*it, file_, pointer_ + "/" + key);
}

std::optional<JsonField> JsonField::find(const std::string& key) const {
  if (!value_->is_object()) fail("expected an object, got " + type_name(*value_));
  const auto it = value_->find(key);
  if (it == value_->end()) return std::nullopt;
  return JsonField(*it, file_, pointer_ + "/" + key);
}

JsonField JsonField::at(std::size_t i) const {
  if (!value_->is_array()) fail("expected an array, got " + type_name(*value_));
  if (i >= value_->size()) fail("index " + std::to_string(i) + " out of range");
  return JsonField((*value_)[i], file_, pointer_ + "/" + std::to_string(i));
}

std::vector<std::string> JsonField::keys() const {
  if (!value_->is_object()) fail("expected an object, got " + type_name(*value_));
  std::vector<std::string> out;
  for (const auto& item : value_->items()) out.push_back(item.key());
  return out;
}

std::string JsonField::as_string() const {
  if (!value_->is_string()) fail("expected a string, got " + type_name(*value_));
  return value_->get<std::string>();
}

double JsonField::as_double() const {
  if (!value_->is_number()) fail("expected a number, got " + type_name(*value_));
  return value_->get<double>();
}

std::vector<double> JsonField::as_doubles(std::size_t n) const {
  if (!value_->is_array() || value_->size() != n) {
    fail("expected an array of " + std::to_string(n) + " numbers");
  }
  std::vector<double> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(at(i).as_double());
  return out;
}

void JsonField::fail(const std::string& what) const {
  throw Error(file_ + ": " + (pointer_.empty() ? std::string("/") : pointer_) + ": " + what);
}

}  // namespace mtg
