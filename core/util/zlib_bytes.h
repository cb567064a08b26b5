#pragma once
// zlib streams (RFC 1950) of byte strings: the form SQLite's sqlar_compress/sqlar_uncompress
// use, so what we store compressed can be read back with the stock sqlite3 shell.

#include <cstddef>
#include <string>
#include <string_view>

namespace mtg {

/// The bytes as one zlib stream at `level` (1 fastest .. 9 smallest). Deterministic for a zlib
/// version: the same input and level give the same output.
std::string zlib_compress(std::string_view bytes, int level = 6);

/// The `size` bytes a zlib stream holds. @throws mtg::Error when the stream is damaged or does
/// not hold exactly `size` bytes.
std::string zlib_uncompress(std::string_view stream, std::size_t size);

}  // namespace mtg
