#include "core/util/json_writer.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

namespace mtg {

void JsonWriter::element() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (!empty_.empty()) {
    if (!empty_.back()) out_ += ',';
    empty_.back() = false;
  }
}

JsonWriter& JsonWriter::open(char bracket) {
  element();
  out_ += bracket;
  empty_.push_back(true);
  return *this;
}

JsonWriter& JsonWriter::close(char bracket) {
  out_ += bracket;
  empty_.pop_back();
  return *this;
}

JsonWriter& JsonWriter::key(std::string_view name) {
  value(name);
  out_ += ':';
  after_key_ = true;
  return *this;
}

JsonWriter& JsonWriter::value(std::string_view text) {
  element();
  // Printable ASCII other than the quote and the backslash is written as it is by dump();
  // anything else (escapes, UTF-8 to validate) goes through dump() itself.
  const bool plain = std::all_of(text.begin(), text.end(), [](char c) {
    return c >= 0x20 && c <= 0x7e && c != '"' && c != '\\';
  });
  if (plain) {
    out_ += '"';
    out_ += text;
    out_ += '"';
  } else {
    out_ += nlohmann::json(std::string(text)).dump();
  }
  return *this;
}

JsonWriter& JsonWriter::value(long long number) {
  element();
  std::array<char, 24> digits{};
  const char* end = std::to_chars(digits.data(), digits.data() + digits.size(), number).ptr;
  out_.append(digits.data(), static_cast<std::size_t>(end - digits.data()));
  return *this;
}

JsonWriter& JsonWriter::value(double number) {
  element();
  if (!std::isfinite(number)) {
    out_ += "null";
    return *this;
  }
  // dump()'s own formatting (Grisu2, then its layout), which std::to_chars does not match.
  std::array<char, 64> digits{};
  const char* end = nlohmann::detail::to_chars(digits.data(), digits.data() + digits.size(), number);
  out_.append(digits.data(), static_cast<std::size_t>(end - digits.data()));
  return *this;
}

JsonWriter& JsonWriter::document(const nlohmann::json& built) {
  element();
  out_ += built.dump();
  return *this;
}

JsonWriter& JsonWriter::array(const std::vector<std::string>& texts) {
  begin_array();
  for (const std::string& t : texts) value(t);
  return end_array();
}

}  // namespace mtg
