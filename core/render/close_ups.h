#pragma once
// The close-ups an observation adds to its platform view (docs/render.md, "What the agent sees"):
// the object in hand, numbered as it was when picked, and the task's look-alikes, each where it
// stands, seen from where the robot stands (or will arrive) at its platform, every other object
// faded: the paper's task-provided image that helps the agent find the object, not its key, so by
// default it carries no number (`numbered`: the assisted variant a run may ask for, recorded in
// its plan). A look-alike's close-up comes with the first observation and again whenever the
// robot stands at its platform and the side it sees it from (or, numbered, its number) changed
// since it was last shown.

#include <map>
#include <string>
#include <vector>

#include "core/render/view.h"
#include "core/tasks/task.h"

namespace mtg::render {

/// What an episode's observations have shown of each look-alike (its platform, side, number),
/// so an unchanged close-up is not sent again.
struct CloseUpsShown {
  std::map<std::string, std::string> last;  // object name -> "<platform>|<side>|<number>"
};

/// `held_number`: the number the held item had when it was picked (0 when nothing is held or it
/// is not known). Adds the item close-up's number and caption to `views` (from
/// observation_views) and appends the look-alike close-ups due now: none under the aid kWords;
/// under kImage each captioned by its label (tasks::close_up_labels), the name the text gives it,
/// not by the words it replaces.
void add_close_ups(const graph::SceneGraph& g, const episode::WorldState& s,
                   const std::vector<tasks::Identification>& lookalikes, int held_number, int width, int height,
                   CloseUpsShown& shown, std::vector<ViewRequest>& views,
                   episode::LookalikeAid aid = episode::LookalikeAid::kBoth, bool numbered = false);

}  // namespace mtg::render
