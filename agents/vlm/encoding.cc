#include "agents/vlm/encoding.h"

#include <openssl/evp.h>

#include "core/util/error.h"

namespace mtg::vlm {

std::string base64_encode(std::span<const std::uint8_t> bytes) {
  std::string out(4 * ((bytes.size() + 2) / 3), '\0');
  const int n = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(out.data()), bytes.data(),
                                static_cast<int>(bytes.size()));
  MTG_DEMAND(n == static_cast<int>(out.size()), "base64 length");
  return out;
}

}  // namespace mtg::vlm
