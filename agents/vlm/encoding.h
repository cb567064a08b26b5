#pragma once
// Byte encodings the adapters need, through OpenSSL: base64 for images in request bodies and
// SHA-256 (core/util/sha256.h) for response-cache keys (the keys cover image bytes, so a weak hash could collide).

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "core/util/sha256.h"

namespace mtg::vlm {

std::string base64_encode(std::span<const std::uint8_t> bytes);
using mtg::sha256_hex;  // core/util/sha256.h: one SHA-256 for the whole project

}  // namespace mtg::vlm
