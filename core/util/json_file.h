#pragma once
// Reading JSON input with errors that name the file and the JSON path of the bad field,
// e.g. "configs/objects/x.object_config.json: /user_defined/r/position: expected 3 numbers".

#include <cstdint>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "core/util/error.h"

namespace mtg {

/// Parses a JSON file. @throws mtg::Error naming the file (and line:column on a syntax error).
nlohmann::json read_json_file(const std::filesystem::path& file);

/// Writes `value` to `file` atomically (temporary file + rename), pretty-printed, sorted keys.
void write_json_file(const std::filesystem::path& file, const nlohmann::json& value);

/// `v` as an integer of type Int: a JSON integer within Int's range. A float (1e126) or a larger
/// integer is refused: nlohmann's get<int>() converts them with undefined behaviour (found by
/// scripts/fuzz). @throws mtg::Error naming `what`.
template <class Int>
Int json_integer(const nlohmann::json& v, const std::string& what) {
  static_assert(std::is_integral_v<Int>);
  const bool fits = v.is_number_unsigned()
                        ? v.get<std::uint64_t>() <= static_cast<std::uint64_t>(std::numeric_limits<Int>::max())
                        : v.is_number_integer() && v.get<std::int64_t>() >= static_cast<std::int64_t>(std::numeric_limits<Int>::min()) &&
                              (std::is_unsigned_v<Int> || v.get<std::int64_t>() <= static_cast<std::int64_t>(std::numeric_limits<Int>::max()));
  if (!fits) throw Error(what + ": " + v.dump().substr(0, 40) + " is not a whole number in range");
  return v.is_number_unsigned() ? static_cast<Int>(v.get<std::uint64_t>()) : static_cast<Int>(v.get<std::int64_t>());
}

/// A JSON value together with where it came from, for error messages.
class JsonField {
 public:
  JsonField(const nlohmann::json& value, std::string file, std::string pointer = "")
      : value_(&value), file_(std::move(file)), pointer_(std::move(pointer)) {}

  /// The member `key`. @throws mtg::Error if this is not an object or `key` is absent.
  JsonField at(const std::string& key) const;
  /// The member `key`, or nullopt if absent. @throws mtg::Error if this is not an object.
  std::optional<JsonField> find(const std::string& key) const;
  /// Element `i` of an array.
  JsonField at(std::size_t i) const;

  bool is_object() const { return value_->is_object(); }
  std::size_t size() const { return value_->size(); }
  std::vector<std::string> keys() const;  // object keys in document order is not kept: sorted

  std::string as_string() const;
  double as_double() const;
  /// An array of exactly n numbers.
  std::vector<double> as_doubles(std::size_t n) const;

  /// "file: /json/pointer: what".
  [[noreturn]] void fail(const std::string& what) const;
  /// "file: /json/pointer", for a warning about this value.
  std::string where() const { return file_ + ": " + (pointer_.empty() ? "/" : pointer_); }

 private:
  const nlohmann::json* value_;
  std::string file_;
  std::string pointer_;
};

}  // namespace mtg
