// JsonWriter: the bytes nlohmann::json::dump() gives for the same document, on the values that
// reach it (task text, names, coordinates, margins that may be unbounded).

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/util/json_writer.h"

namespace mtg {
namespace {

std::string written(double x) {
  std::string out;
  JsonWriter(out).value(x);
  return out;
}

std::string written(const std::string& text) {
  std::string out;
  JsonWriter(out).value(text);
  return out;
}

TEST(JsonWriter, NumbersReadAsDumpPrintsThem) {
  const double inf = std::numeric_limits<double>::infinity();
  for (const double x : {0.0, -0.0, 1.0, -3.0, 0.1, 1.0 / 3.0, 1e-5, 1.5e-7, 123456789012345678.0, 1e21, 1e300,
                         -2.5e-300, 5e-324, 0.30000000000000004, 2.718281828459045, 1.2345, 1e15, 1e16,
                         std::nextafter(1.0, 2.0), inf, -inf, std::nan("")}) {
    EXPECT_EQ(written(x), nlohmann::json(x).dump()) << x;
  }
  for (const long long n : {0LL, 7LL, -42LL, std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max()}) {
    std::string out;
    JsonWriter(out).value(n);
    EXPECT_EQ(out, nlohmann::json(n).dump()) << n;
  }
}

TEST(JsonWriter, TextIsEscapedAsDumpEscapesIt) {
  for (const std::string& text : std::vector<std::string>{"", "plain words", "a \"quoted\" word", "back\\slash", "tab\tand\nnewline",
                                 std::string("nul\0byte", 8), "\x01\x1f\x7f", "caf\xc3\xa9 \xe2\x86\x92 \xf0\x9f\x8d\xb5",
                                 "slash / stays"}) {
    EXPECT_EQ(written(text), nlohmann::json(text).dump()) << text;
  }
  std::string out;
  EXPECT_THROW(JsonWriter(out).value(std::string("\xff\xfe")), nlohmann::json::type_error)
      << "text that is not UTF-8 is refused, as dump() refuses it";
}

TEST(JsonWriter, ContainersNestAsInDump) {
  std::string out;
  JsonWriter w(out);
  w.begin_object();
  w.key("a").array({"x", "y"});
  w.key("b").begin_array().end_array();
  w.key("c").begin_array();
  w.begin_object().key("k").value(1).end_object();
  w.begin_object().end_object();
  w.document(nlohmann::json{{"z", nullptr}, {"m", {1, 2.5}}});
  w.end_array();
  w.key("d").value(0.25);
  w.end_object();
  const nlohmann::json expected = {{"a", {"x", "y"}},
                                   {"b", nlohmann::json::array()},
                                   {"c", {{{"k", 1}}, nlohmann::json::object(), {{"z", nullptr}, {"m", {1, 2.5}}}}},
                                   {"d", 0.25}};
  EXPECT_EQ(out, expected.dump());
}

}  // namespace
}  // namespace mtg
