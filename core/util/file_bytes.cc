#include "core/util/file_bytes.h"

#include <fstream>
#include <iterator>

#include "core/util/atomic_file.h"
#include "core/util/error.h"

namespace mtg {

std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": cannot be read");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), {});
  if (in.bad()) throw Error(file.string() + ": cannot be read");
  return bytes;
}

void write_file_bytes_atomically(const std::filesystem::path& file, std::span<const std::uint8_t> bytes) {
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  write_file_atomically(file, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace mtg
