#include "bus/authenticator.h"

#include <fcntl.h>
#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/rand.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "bus/header.h"
#include "core/util/error.h"
#include "core/util/text.h"

namespace mtg::bus {
namespace {

std::vector<std::uint8_t> hmac_sha256(EVP_MAC* mac, std::span<const std::uint8_t> key, std::span<const std::uint8_t> a,
                                      std::span<const std::uint8_t> b) {
  // HMAC over a || b without copying them together: the streaming interface.
  std::vector<std::uint8_t> out(EVP_MAX_MD_SIZE);
  EVP_MAC_CTX* ctx = EVP_MAC_CTX_new(mac);
  char digest[] = "SHA256";
  const OSSL_PARAM params[] = {OSSL_PARAM_construct_utf8_string("digest", digest, 0), OSSL_PARAM_construct_end()};
  std::size_t len = 0;
  const bool ok = ctx != nullptr && EVP_MAC_init(ctx, key.data(), key.size(), params) == 1 &&
                  EVP_MAC_update(ctx, a.data(), a.size()) == 1 && EVP_MAC_update(ctx, b.data(), b.size()) == 1 &&
                  EVP_MAC_final(ctx, out.data(), &len, out.size()) == 1;
  EVP_MAC_CTX_free(ctx);
  if (!ok) throw Error("bus authentication: HMAC-SHA-256 is not available from OpenSSL");
  out.resize(len);
  return out;
}

std::span<const std::uint8_t> bytes_of(const std::string& s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

}  // namespace

Authenticator::Authenticator(std::string secret)
    : secret_(std::move(secret)), mac_(EVP_MAC_fetch(nullptr, "HMAC", nullptr), &EVP_MAC_free) {
  // Fetched once: every message on a shared bus is signed or checked with it.
  if (!mac_) throw Error("bus authentication: HMAC-SHA-256 is not available from OpenSSL");
}

std::string Authenticator::read_secret(const std::filesystem::path& file) {
  const std::string secret = trim_whitespace(read_text_file(file, "bus key file"));
  if (secret.size() < 16) {
    throw Error(file.string() + ": the bus key must hold at least 16 bytes (e.g. `head -c 32 /dev/urandom | "
                "base64 > " + file.filename().string() + "`)");
  }
  return secret;
}

std::vector<std::uint8_t> Authenticator::run_key(const std::string& run_id) const {
  return run_keys_.get(run_id, [&] {
    const std::string label = "mtg-bus-run:" + run_id;
    return hmac_sha256(mac_.get(), bytes_of(secret_), bytes_of(label), {});
  });
}

std::vector<std::uint8_t> Authenticator::tag(const std::string& channel, std::span<const std::uint8_t> payload) const {
  const auto header = peek_header(payload);
  const std::string run_id = header ? header->run_id : std::string();
  const std::string prefix = channel + '\0';
  return hmac_sha256(mac_.get(), run_key(run_id), bytes_of(prefix), payload);
}

std::vector<std::uint8_t> Authenticator::sign(const std::string& channel, std::span<const std::uint8_t> payload) const {
  std::vector<std::uint8_t> out(payload.begin(), payload.end());
  const auto t = tag(channel, payload);
  out.insert(out.end(), t.begin(), t.end());
  return out;
}

std::optional<std::span<const std::uint8_t>> Authenticator::verify(const std::string& channel,
                                                                   std::span<const std::uint8_t> message) const {
  if (message.size() < kTagBytes) {
    ++rejected_;
    return std::nullopt;
  }
  const auto payload = message.first(message.size() - kTagBytes);
  const auto expected = tag(channel, payload);
  if (CRYPTO_memcmp(expected.data(), message.data() + payload.size(), kTagBytes) != 0) {
    ++rejected_;
    return std::nullopt;
  }
  return payload;
}

std::string shared_bus_key_file(const std::string& key_file) {
  std::string file = key_file;
  if (file.empty()) {
    if (const char* env = std::getenv("MTG_BUS_KEY"); env != nullptr) file = env;
  }
  if (file.empty()) {
    throw Error("a bus shared between hosts needs a key: --bus-key FILE or $MTG_BUS_KEY, the same secret on every "
                "host (e.g. `head -c 32 /dev/urandom | base64 > bus.key; chmod 600 bus.key`; docs/multihost.md)");
  }
  return file;
}

void create_key_file(const std::filesystem::path& file) {
  unsigned char bytes[32];
  if (RAND_bytes(bytes, sizeof bytes) != 1) throw Error("cannot draw a bus key: OpenSSL RAND_bytes failed");
  std::string secret;
  for (const unsigned char b : bytes) {
    char hex[3];
    std::snprintf(hex, sizeof hex, "%02x", b);
    secret += hex;
  }
  secret += '\n';
  // Owner-only from its creation, and only if absent (a resume keeps its key). No umask: that is
  // the whole process's.
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0 && errno == EEXIST) return;
  if (fd < 0) throw Error("cannot write the bus key " + file.string() + ": " + std::strerror(errno));
  const bool written = ::write(fd, secret.data(), secret.size()) == static_cast<ssize_t>(secret.size());
  ::close(fd);
  if (!written) throw Error("cannot write the bus key " + file.string());
}

std::shared_ptr<const Authenticator> shared_bus_authenticator(const std::string& key_file) {
  return std::make_shared<const Authenticator>(Authenticator::read_secret(shared_bus_key_file(key_file)));
}

}  // namespace mtg::bus
