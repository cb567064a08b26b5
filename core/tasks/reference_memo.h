#pragma once
// References found in one base state (the scene as task generation starts from it), shared by
// every thread naming objects in that state or in a state derived from it. refer() reads one
// furniture platform only, so a question about a platform that looks exactly as it does in the
// base state (the same objects, in the same order, with the same footprints and supports) has
// the base state's answer: it is worked out once and kept. A platform that looks different (a
// Level 3 step moved something onto or off it), or whose arrival view shows something else (an
// item moved into or out of view), is answered afresh and not kept.

#include <optional>

#include "core/episode/world_state.h"
#include "core/tasks/referring.h"
#include "core/util/memo_table.h"

namespace mtg::tasks {

class ReferenceMemo {
 public:
  /// `g`, `base` and `seeing` (when given) must outlive the memo.
  ReferenceMemo(const graph::SceneGraph& g, const episode::WorldState& base, Ambiguity rule,
                const render::VisibilityOracle* seeing = nullptr);

  /// refer() naming `object` on `platform` in `s` (nothing held), and also with `held_item` in
  /// hand when it is valid (an anchor while the item from its platform is being placed): the
  /// same answer as refer() itself, from whichever thread and in whatever order asked.
  Referral refer(const episode::WorldState& s, graph::ObjectId object, graph::PlatformId platform,
                 graph::ObjectId held_item) const;

  Ambiguity rule() const { return rule_; }
  const render::VisibilityOracle* seeing() const { return seeing_; }

 private:
  bool as_in_base(const episode::WorldState& s, graph::PlatformId platform) const;

  const graph::SceneGraph& g_;
  const episode::WorldState& base_;
  Ambiguity rule_;
  const render::VisibilityOracle* seeing_;
  std::vector<std::string> base_views_;  // per platform, its arrival view's key in `base` ("" unknown)
  mutable MemoTable<Referral> kept_;  // by object, platform, held item
};

/// refer() for `object` on `platform` in `s`, and also with `held_item` in hand when it is valid.
Referral refer_in(const graph::SceneGraph& g, const episode::WorldState& s, graph::ObjectId object,
                  graph::PlatformId platform, graph::ObjectId held_item, Ambiguity rule,
                  const render::VisibilityOracle* seeing = nullptr);

}  // namespace mtg::tasks
