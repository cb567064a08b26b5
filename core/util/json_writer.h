#pragma once
// JSON text written straight from values into a string: the bytes nlohmann::json::dump() gives
// for the same document, without building the document first. Writing a task database spent a
// third of its time building nlohmann objects only to print them (docs/tasks.md, "Storage").
//
// The caller gives an object's keys in the order dump() prints them (std::map's: byte order);
// json_writer_test holds the writer to dump() on the values that reach it.

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace mtg {

class JsonWriter {
 public:
  /// Appends to `out`, which must outlive the writer.
  explicit JsonWriter(std::string& out) : out_(out) {}

  JsonWriter& begin_object() { return open('{'); }
  JsonWriter& end_object() { return close('}'); }
  JsonWriter& begin_array() { return open('['); }
  JsonWriter& end_array() { return close(']'); }
  /// The next member's name; its value follows.
  JsonWriter& key(std::string_view name);
  /// @throws nlohmann::json::type_error for text that is not UTF-8, as dump() does.
  JsonWriter& value(std::string_view text);
  JsonWriter& value(const char* text) { return value(std::string_view(text)); }
  JsonWriter& value(const std::string& text) { return value(std::string_view(text)); }
  JsonWriter& value(long long number);
  JsonWriter& value(int number) { return value(static_cast<long long>(number)); }
  /// Shortest text that reads back as the same double; null when not finite (as dump()).
  JsonWriter& value(double number);
  /// A document already built: its dump().
  JsonWriter& document(const nlohmann::json& built);
  JsonWriter& array(const std::vector<std::string>& texts);

 private:
  void element();  // the comma before every element of a container but its first
  JsonWriter& open(char bracket);
  JsonWriter& close(char bracket);

  std::string& out_;
  std::vector<bool> empty_;  // per open container: nothing written in it yet
  bool after_key_ = false;
};

}  // namespace mtg
