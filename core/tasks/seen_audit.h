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
#include "core/tasks/task.h"

namespace mtg::tasks {

class SeenAudit {
 public:
  /// `g` and `geometry` must outlive the audit; `options` the task set's (its thresholds).
  SeenAudit(const graph::SceneGraph& g, const render::SceneGeometry& geometry, TaskOptions options);

  /// Every broken promise of the task about what the agent sees, one line each.
  std::vector<std::string> check(const Task& task) const;

  /// Distinct views drawn so far (views are remembered by the exact state they show).
  std::size_t views_drawn() const { return views_.size(); }

 private:
  struct View;
  View& view(const episode::WorldState& s, graph::PlatformId platform) const;
  // The view's marks, laid out on its pass (once, when first asked).
  void lay_out_marks(View& v, const episode::WorldState& s, graph::PlatformId platform) const;

  const graph::SceneGraph& g_;
  const render::SceneGeometry& geometry_;
  TaskOptions options_;
  mutable std::map<std::string, std::shared_ptr<View>> views_;
};

}  // namespace mtg::tasks
