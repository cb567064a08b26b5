#pragma once
// Small text helpers for configuration-like files (keys, prompt templates, price tables).

#include <filesystem>
#include <string>
#include <string_view>

namespace mtg {

/// `s` without leading and trailing spaces, tabs and line breaks.
std::string trim_whitespace(std::string_view s);

/// `s` safe inside HTML or SVG text and double-quoted attributes: & < > " ' as entities.
std::string escape_markup(std::string_view s);

/// The whole file. @throws mtg::Error "<file>: cannot read the <what>".
std::string read_text_file(const std::filesystem::path& file, const std::string& what);

}  // namespace mtg
