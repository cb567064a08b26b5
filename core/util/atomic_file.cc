#include "core/util/atomic_file.h"

#include <fstream>

#include "core/util/error.h"

namespace mtg {

std::filesystem::path partial_path(const std::filesystem::path& file) { return file.string() + ".partial"; }

void write_file_atomically(const std::filesystem::path& file, const std::function<void(std::ostream&)>& write) {
  const std::filesystem::path tmp = partial_path(file);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(file.string() + ": cannot write");
    write(out);
    if (!out) throw Error(file.string() + ": write failed");
  }
  std::filesystem::rename(tmp, file);
}

}  // namespace mtg
