#pragma once
// A file's whole contents, for assertions: "" when it cannot be read (the assertion then shows
// what was expected instead of throwing).

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace mtg::testing {

inline std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace mtg::testing
