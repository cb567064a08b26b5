#include "bus/authenticator.h"

#include <fcntl.h>
#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/rand.h>
#include <unistd.h>

#include <algorithm>
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
  if (RAND_bytes(session_.data(), static_cast<int>(session_.size())) != 1) {
    throw Error("bus authentication: cannot draw a session nonce (OpenSSL RAND_bytes failed)");
  }
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

std::vector<std::uint8_t> Authenticator::tag(const std::string& channel, std::span<const std::uint8_t> payload,
                                             std::span<const std::uint8_t> trailer) const {
  const auto header = peek_header(payload);
  const std::string run_id = header ? header->run_id : std::string();
  // The channel, then payload, nonce and number as they lie in the message (one span).
  const std::string prefix = channel + '\0';
  return hmac_sha256(mac_.get(), run_key(run_id), bytes_of(prefix),
                     {payload.data(), payload.size() + trailer.size()});
}

std::vector<std::uint8_t> Authenticator::sign(const std::string& channel, std::span<const std::uint8_t> payload) const {
  std::vector<std::uint8_t> out;
  out.reserve(payload.size() + kTrailerBytes);
  out.assign(payload.begin(), payload.end());
  out.insert(out.end(), session_.begin(), session_.end());
  const std::uint64_t number = ++sent_;
  for (int shift = 56; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(number >> shift));
  const auto t = tag(channel, {out.data(), payload.size()}, {out.data() + payload.size(), out.size() - payload.size()});
  out.insert(out.end(), t.begin(), t.end());
  return out;
}

std::optional<std::span<const std::uint8_t>> Authenticator::verify(const std::string& channel,
                                                                   std::span<const std::uint8_t> message,
                                                                   std::int64_t delivery) const {
  if (message.size() < kTrailerBytes) {
    ++rejected_;
    return std::nullopt;
  }
  const auto payload = message.first(message.size() - kTrailerBytes);
  const auto session_and_number = message.subspan(payload.size(), ReplayWindow::kNonceBytes + 8);
  const auto expected = tag(channel, payload, session_and_number);
  if (CRYPTO_memcmp(expected.data(), message.data() + message.size() - kTagBytes, kTagBytes) != 0) {
    ++rejected_;
    return std::nullopt;
  }
  ReplayWindow::Nonce session;
  std::copy_n(session_and_number.begin(), session.size(), session.begin());
  std::uint64_t number = 0;
  for (std::size_t i = 0; i < 8; ++i) number = (number << 8) | session_and_number[session.size() + i];
  if (!taken_.take(session, number, delivery)) {
    ++replayed_;
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

namespace {

std::string random_hex(std::size_t bytes, const std::string& what) {
  std::vector<unsigned char> drawn(bytes);
  if (RAND_bytes(drawn.data(), static_cast<int>(drawn.size())) != 1) {
    throw Error("cannot draw " + what + ": OpenSSL RAND_bytes failed");
  }
  std::string out;
  for (const unsigned char b : drawn) {
    char hex[3];
    std::snprintf(hex, sizeof hex, "%02x", b);
    out += hex;
  }
  return out;
}

}  // namespace

std::string draw_session_token() { return random_hex(16, "a session token"); }

void create_key_file(const std::filesystem::path& file) {
  const std::string secret = random_hex(32, "a bus key") + '\n';
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
