#pragma once
// Whole files as bytes: read in one go, written whole or not at all (atomic_file.h). Recordings
// of episodes, images and the like, whose writers and readers must never see half a file.

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace mtg {

/// The bytes of `file`. @throws mtg::Error naming the file when it cannot be read.
std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& file);

/// Writes `bytes` to `file` atomically (write_file_atomically), making its folder if need be.
/// @throws mtg::Error naming the file when it cannot be written.
void write_file_bytes_atomically(const std::filesystem::path& file, std::span<const std::uint8_t> bytes);

}  // namespace mtg
