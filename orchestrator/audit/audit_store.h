#pragma once
// An audit's folder (docs/view.md, "mtg audit"): audit.sqlite with what the page shows for each
// sampled task, the truth it is checked against (never served), and the answers a person gave;
// images/ with the observations' images. Answers are stored as they come, per rater (several
// people judge the same draw, each with `mtg audit --rater NAME`), so an audit stopped at any
// point goes on where it was.
//
//   meta    (key TEXT PRIMARY KEY, value TEXT)   format, tasks, config_hash, per_level, seed, scene, ...
//   items   (idx INTEGER PRIMARY KEY, task_id TEXT, level INTEGER, page TEXT, truth TEXT)
//   answers (idx INTEGER, rater TEXT, valid INTEGER, reason TEXT, note TEXT, picks TEXT, seq INTEGER,
//            PRIMARY KEY (idx, rater))
//   progress (idx INTEGER, rater TEXT, revealed INTEGER, picks TEXT, PRIMARY KEY (idx, rater))

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/store/sqlite.h"

namespace mtg::orchestrator::audit {

inline constexpr const char* kAuditFormat = "mtg-audit/2";
/// The rater of an audit judged without --rater.
inline constexpr const char* kDefaultRater = "rater";

/// Why a task is not valid, as the page offers it.
enum class Reason { kOccluded, kUnclearNoun, kUnreadableMarks, kAmbiguousText, kInfeasible, kOther };
const char* to_string(Reason r);
/// @throws mtg::Error naming the value and the accepted ones.
Reason reason_from_string(const std::string& name);
const std::vector<Reason>& all_reasons();

struct Answer {
  bool valid = false;
  std::optional<Reason> reason;         // when not valid
  std::string note;
  std::map<std::string, std::string> picks;  // question id -> "o3" or "5" ("" when the person did not know)
  std::int64_t seq = 0;                 // the order answers were given in
};

struct Item {
  int index = 0;
  std::string task_id;
  int level = 0;
  nlohmann::json page;   // what the page shows (no truth)
  nlohmann::json truth;  // question id -> the right key
};

class AuditStore {
 public:
  /// Opens (creating when `create`) DIR/audit.sqlite. @throws mtg::Error naming the file.
  AuditStore(const std::filesystem::path& dir, bool create);

  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path images_dir() const { return dir_ / "images"; }

  /// The meta table; set_meta writes it (a build), meta reads it.
  std::map<std::string, std::string> meta();
  void set_meta(const std::map<std::string, std::string>& values);

  void add_item(const Item& item);
  std::vector<Item> items();
  std::optional<Item> item(int index);

  /// How far a rater has gone through an item's observations (revealed in order, so a question's
  /// answer cannot be read from a later one) and the picks given so far.
  struct Progress {
    int revealed = 0;  // observations 0..revealed are shown
    std::map<std::string, std::string> picks;
  };
  Progress progress(int index, const std::string& rater);
  void put_progress(int index, const std::string& rater, const Progress& progress);

  void put_answer(int index, const std::string& rater, const Answer& answer);
  /// One rater's answers, by item.
  std::map<int, Answer> answers(const std::string& rater);
  /// Every rater's answers: rater -> item -> answer.
  std::map<std::string, std::map<int, Answer>> all_answers();

 private:
  std::filesystem::path dir_;
  store::Database db_;
};

}  // namespace mtg::orchestrator::audit
