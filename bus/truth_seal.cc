#include "bus/truth_seal.h"

#include <fcntl.h>
#include <openssl/evp.h>
#include <openssl/rand.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "core/util/error.h"

namespace mtg::bus {
namespace {

constexpr std::size_t kNonceBytes = 12, kTagBytes = 16;

std::vector<std::uint8_t> aad_of(const mtg::header_t& h) {
  const std::string s = h.run_id + '\0' + std::to_string(h.episode_id) + '\0' + std::to_string(h.attempt);
  return {s.begin(), s.end()};
}

using CipherCtx = std::unique_ptr<EVP_CIPHER_CTX, decltype(&EVP_CIPHER_CTX_free)>;

CipherCtx new_ctx() {
  CipherCtx ctx(EVP_CIPHER_CTX_new(), &EVP_CIPHER_CTX_free);
  if (!ctx) throw Error("truth seal: OpenSSL cannot make a cipher context");
  return ctx;
}

}  // namespace

TruthSeal TruthSeal::random() {
  std::array<std::uint8_t, kKeyBytes> key{};
  if (RAND_bytes(key.data(), static_cast<int>(key.size())) != 1) throw Error("truth seal: OpenSSL RAND_bytes failed");
  return TruthSeal(key);
}

TruthSeal TruthSeal::derived(const std::string& secret, const std::string& run_id) {
  const std::string label = "mtg-truth:" + run_id;
  std::array<std::uint8_t, kKeyBytes> key{};
  std::size_t len = 0;
  if (EVP_Q_mac(nullptr, "HMAC", nullptr, "SHA256", nullptr, secret.data(), secret.size(),
                reinterpret_cast<const unsigned char*>(label.data()), label.size(), key.data(), key.size(),
                &len) == nullptr ||
      len != key.size()) {
    throw Error("truth seal: HMAC-SHA-256 is not available from OpenSSL");
  }
  return TruthSeal(key);
}

TruthSeal TruthSeal::from_file(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw Error(file.string() + ": cannot read the run's answer key");
  std::string hex;
  in >> hex;
  std::array<std::uint8_t, kKeyBytes> key{};
  if (hex.size() != 2 * kKeyBytes) throw Error(file.string() + ": an answer key is 64 hex digits");
  for (std::size_t i = 0; i < kKeyBytes; ++i) {
    unsigned v = 0;
    if (std::sscanf(hex.c_str() + 2 * i, "%2x", &v) != 1) throw Error(file.string() + ": an answer key is 64 hex digits");
    key[i] = static_cast<std::uint8_t>(v);
  }
  return TruthSeal(key);
}

void TruthSeal::write(const std::filesystem::path& file) const {
  std::string hex;
  for (const std::uint8_t b : key_) {
    char two[3];
    std::snprintf(two, sizeof two, "%02x", b);
    hex += two;
  }
  hex += '\n';
  // Owner-only from its creation (no umask games: that is the whole process's).
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  const bool ok = fd >= 0 && ::write(fd, hex.data(), hex.size()) == static_cast<ssize_t>(hex.size());
  if (fd >= 0) ::close(fd);
  if (!ok) throw Error(file.string() + ": cannot write the run's answer key");
}

TruthSeal TruthSeal::for_run_folder(const std::filesystem::path& dir, const TruthSeal& fresh) {
  const auto file = dir / kFileName;
  std::error_code ec;
  if (std::filesystem::exists(file, ec)) return from_file(file);
  fresh.write(file);
  return fresh;
}

mtg::episode_truth_t TruthSeal::seal(const mtg::episode_truth_t& truth) const {
  if (is_sealed(truth)) return truth;
  const std::string plain =
      nlohmann::json{{"goal", truth.goal_json}, {"plan", truth.oracle_plan}, {"identify", truth.identify_json}}.dump();
  std::vector<std::uint8_t> out(kNonceBytes + plain.size() + kTagBytes);
  if (RAND_bytes(out.data(), kNonceBytes) != 1) throw Error("truth seal: OpenSSL RAND_bytes failed");
  const auto aad = aad_of(truth.header);
  auto ctx = new_ctx();
  int len = 0;
  const bool ok =
      EVP_EncryptInit_ex(ctx.get(), EVP_aes_256_gcm(), nullptr, key_.data(), out.data()) == 1 &&
      EVP_EncryptUpdate(ctx.get(), nullptr, &len, aad.data(), static_cast<int>(aad.size())) == 1 &&
      EVP_EncryptUpdate(ctx.get(), out.data() + kNonceBytes, &len, reinterpret_cast<const unsigned char*>(plain.data()),
                        static_cast<int>(plain.size())) == 1 &&
      EVP_EncryptFinal_ex(ctx.get(), out.data() + kNonceBytes + len, &len) == 1 &&
      EVP_CIPHER_CTX_ctrl(ctx.get(), EVP_CTRL_GCM_GET_TAG, static_cast<int>(kTagBytes),
                          out.data() + kNonceBytes + plain.size()) == 1;
  if (!ok) throw Error("truth seal: AES-256-GCM is not available from OpenSSL");
  mtg::episode_truth_t sealed = truth;
  sealed.goal_json.clear();
  sealed.oracle_plan.clear();
  sealed.n_oracle = 0;
  sealed.identify_json.clear();
  sealed.sealed = std::move(out);
  sealed.n_sealed = static_cast<std::int32_t>(sealed.sealed.size());
  return sealed;
}

mtg::episode_truth_t TruthSeal::open(const mtg::episode_truth_t& truth) const {
  if (!is_sealed(truth)) return truth;
  const auto where = [&] {
    return "the answers of episode " + std::to_string(truth.header.episode_id) + " attempt " +
           std::to_string(truth.header.attempt) + " (run " + truth.header.run_id + ")";
  };
  const std::vector<std::uint8_t>& in = truth.sealed;
  if (in.size() < kNonceBytes + kTagBytes) throw Error(where() + " are sealed but too short to open");
  const std::size_t n = in.size() - kNonceBytes - kTagBytes;
  std::string plain(n, '\0');
  const auto aad = aad_of(truth.header);
  std::vector<std::uint8_t> tag(in.end() - kTagBytes, in.end());
  auto ctx = new_ctx();
  int len = 0;
  const bool ok =
      EVP_DecryptInit_ex(ctx.get(), EVP_aes_256_gcm(), nullptr, key_.data(), in.data()) == 1 &&
      EVP_DecryptUpdate(ctx.get(), nullptr, &len, aad.data(), static_cast<int>(aad.size())) == 1 &&
      EVP_DecryptUpdate(ctx.get(), reinterpret_cast<unsigned char*>(plain.data()), &len, in.data() + kNonceBytes,
                        static_cast<int>(n)) == 1 &&
      EVP_CIPHER_CTX_ctrl(ctx.get(), EVP_CTRL_GCM_SET_TAG, static_cast<int>(kTagBytes), tag.data()) == 1 &&
      EVP_DecryptFinal_ex(ctx.get(), reinterpret_cast<unsigned char*>(plain.data()) + len, &len) == 1;
  if (!ok) throw Error(where() + " do not open with this run's key (another run's, forged or damaged)");
  const nlohmann::json j = nlohmann::json::parse(plain, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw Error(where() + " opened to something that is not JSON");
  mtg::episode_truth_t out = truth;
  out.sealed.clear();
  out.n_sealed = 0;
  out.goal_json = j.value("goal", "");
  out.oracle_plan = j.value("plan", std::vector<std::string>{});
  out.n_oracle = static_cast<std::int16_t>(out.oracle_plan.size());
  out.identify_json = j.value("identify", "");
  return out;
}

RecordedTruths::RecordedTruths(const std::filesystem::path& run_dir) : key_file_(run_dir / TruthSeal::kFileName) {
  std::error_code ec;
  if (std::filesystem::exists(key_file_, ec)) seal_ = TruthSeal::from_file(key_file_);
}

mtg::episode_truth_t RecordedTruths::open(const mtg::episode_truth_t& truth) const {
  if (!is_sealed(truth)) return truth;
  if (!seal_) {
    throw Error("the recorded answers are sealed and their key " + key_file_.string() +
                " is missing (copy it with the run folder)");
  }
  return seal_->open(truth);
}

}  // namespace mtg::bus
