#include "agents/vlm/encoding.h"

#include <openssl/evp.h>
#include <openssl/sha.h>

#include "core/util/error.h"

namespace mtg::vlm {

std::string base64_encode(std::span<const std::uint8_t> bytes) {
  std::string out(4 * ((bytes.size() + 2) / 3), '\0');
  const int n = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(out.data()), bytes.data(),
                                static_cast<int>(bytes.size()));
  MTG_DEMAND(n == static_cast<int>(out.size()), "base64 length");
  return out;
}

std::string sha256_hex(std::string_view text) {
  unsigned char digest[SHA256_DIGEST_LENGTH];
  unsigned int len = 0;
  MTG_DEMAND(EVP_Digest(text.data(), text.size(), digest, &len, EVP_sha256(), nullptr) == 1, "SHA-256");
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(2 * len);
  for (unsigned int i = 0; i < len; ++i) {
    out += kHex[digest[i] >> 4];
    out += kHex[digest[i] & 15];
  }
  return out;
}

}  // namespace mtg::vlm
