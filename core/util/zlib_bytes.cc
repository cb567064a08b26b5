#include "core/util/zlib_bytes.h"

#include <zlib.h>

#include "core/util/error.h"

namespace mtg {

std::string zlib_compress(std::string_view bytes, int level) {
  uLongf size = compressBound(static_cast<uLong>(bytes.size()));
  std::string out(size, '\0');
  const int rc = compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(bytes.data()),
                           static_cast<uLong>(bytes.size()), level);
  if (rc != Z_OK) throw Error("zlib: compression failed (" + std::to_string(rc) + ")");
  out.resize(size);
  out.shrink_to_fit();  // the bound is well above what zlib needs: compressed text is often kept
  return out;
}

std::string zlib_uncompress(std::string_view stream, std::size_t size) {
  std::string out(size, '\0');
  uLongf got = static_cast<uLongf>(size);
  const int rc = uncompress(reinterpret_cast<Bytef*>(out.data()), &got, reinterpret_cast<const Bytef*>(stream.data()),
                            static_cast<uLong>(stream.size()));
  if (rc != Z_OK || got != size) {
    throw Error("zlib: damaged stream (" + std::string(rc == Z_OK ? "size differs" : zError(rc)) + ")");
  }
  return out;
}

}  // namespace mtg
