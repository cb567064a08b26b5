#pragma once
// Checking what a stored task asks of the agent's eyes, from id passes drawn afresh the way the
// renderer draws them (not from the generator's windows and memos): each object the text names
// and each one a reference counts is clearly visible in the arrival view the agent gets where
// that part starts, in the picture's order for ranks, and the item's number has a readable
// place in the marked view or a zoom of it (docs/tasks.md, "Seen, not only there"). Used by the
// tests over the shipped task sets and by `mtg audit`.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/render/scene_geometry.h"
#include "core/render/visibility.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

class SeenAudit {
 public:
  /// `g` and `geometry` must outlive the audit; `options` the task set's (its thresholds).
  SeenAudit(const graph::SceneGraph& g, const render::SceneGeometry& geometry, TaskOptions options);

  /// Every broken promise of the task about what the agent sees, one line each.
  std::vector<std::string> check(const Task& task) const;

  /// Distinct views drawn so far (views are remembered by the exact state they show).
  std::size_t views_drawn() const { return drawn_; }

 private:
  struct View;
  std::shared_ptr<View> view(const episode::WorldState& s, graph::PlatformId platform) const;
  // Picture k's id pass (drawn when first asked).
  const render::IdView& ids(View& v, std::size_t k) const;
  // Whether object o's number has a readable place in one of the view's pictures (laid out, and
  // checked against the rules into `problems`, when first asked).
  bool readable(View& v, graph::ObjectId o, std::vector<std::string>& problems) const;

  const graph::SceneGraph& g_;
  const render::SceneGeometry& geometry_;
  TaskOptions options_;
  mutable std::map<std::string, std::shared_ptr<View>> views_;
  mutable std::size_t drawn_ = 0;
};

}  // namespace mtg::tasks
