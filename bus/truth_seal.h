#pragma once
// An episode's answers (episode_truth_t: the goal, the oracle plan, the look-alikes) travel
// sealed: AES-256-GCM under a key of the run that only the processes meant to read them hold
// (the judge, the scene-graph service, the built-in oracle, the orchestrator and its workers),
// so any other process on the bus (an agent, a plain UDP socket on a shared bus) sees the
// header and the task id and nothing else. The header's run, episode and attempt are bound to
// the ciphertext, so a sealed answer cannot be passed off for another episode.
//
// The key: a local run draws one and keeps it in RUN/truth.key (mode 600; a resume reads it
// back), which the viewer, `rejudge`, `replay` and `export` read too. A run over a shared bus
// derives it from the bus secret every host holds, HMAC-SHA-256(secret, "mtg-truth:" + run id),
// and the coordinator writes the derived key (never the secret) into its run folder.
// docs/bus.md "Ground truth".

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "mtg/episode_truth_t.hpp"

namespace mtg::bus {

class TruthSeal {
 public:
  static constexpr std::size_t kKeyBytes = 32;
  /// The key file's name in a run folder.
  static constexpr const char* kFileName = "truth.key";

  /// A fresh random key.
  static TruthSeal random();
  /// The key every host of a shared-bus run derives from the bus secret.
  static TruthSeal derived(const std::string& secret, const std::string& run_id);
  /// Reads a key file (64 hex digits). @throws mtg::Error naming the file.
  static TruthSeal from_file(const std::filesystem::path& file);
  /// The key of a run folder: its truth.key, written first from `fresh` when there is none yet
  /// (a resume keeps the key its recordings were sealed with). @throws mtg::Error naming the file.
  static TruthSeal for_run_folder(const std::filesystem::path& dir, const TruthSeal& fresh);
  /// Writes the key, owner-only. @throws mtg::Error naming the file.
  void write(const std::filesystem::path& file) const;

  /// `truth` with its goal, plan and look-alikes moved into `sealed`; a sealed truth as it is.
  mtg::episode_truth_t seal(const mtg::episode_truth_t& truth) const;
  /// The truth in clear; one never sealed as it is. @throws mtg::Error when it does not open
  /// with this key (another run's key, a forged or damaged message).
  mtg::episode_truth_t open(const mtg::episode_truth_t& truth) const;

 private:
  explicit TruthSeal(const std::array<std::uint8_t, kKeyBytes>& key) : key_(key) {}
  std::array<std::uint8_t, kKeyBytes> key_{};
};

inline bool is_sealed(const mtg::episode_truth_t& truth) { return truth.n_sealed > 0; }

/// Opens what a run folder recorded: with its truth.key, or a clear error naming the file when
/// the answers are sealed and the key is not there (a run copied without it).
class RecordedTruths {
 public:
  explicit RecordedTruths(const std::filesystem::path& run_dir);
  /// @throws mtg::Error naming the missing key or the episode whose answers do not open.
  mtg::episode_truth_t open(const mtg::episode_truth_t& truth) const;

 private:
  std::filesystem::path key_file_;
  std::optional<TruthSeal> seal_;
};

}  // namespace mtg::bus
