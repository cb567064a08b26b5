#pragma once
// Writing a file so that readers never see half of it: the content goes to `<file>.partial`,
// which is renamed over `file` once complete. An interrupted writer leaves the old file (or
// none) and at most a stale `.partial`.

#include <filesystem>
#include <functional>
#include <ostream>

namespace mtg {

/// Calls `write(stream)` on a binary stream to `<file>.partial`, then renames it to `file`.
/// @throws mtg::Error naming `file` when it cannot be written.
void write_file_atomically(const std::filesystem::path& file, const std::function<void(std::ostream&)>& write);

/// `<file>.partial`: where write_file_atomically() and the task database build a file.
std::filesystem::path partial_path(const std::filesystem::path& file);

}  // namespace mtg
