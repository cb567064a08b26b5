#include "core/render/close_ups.h"

#include <algorithm>

#include "core/tasks/lookalike_aid.h"

namespace mtg::render {

void add_close_ups(const graph::SceneGraph& g, const episode::WorldState& s,
                   const std::vector<tasks::Identification>& lookalikes, int held_number, int width, int height,
                   CloseUpsShown& shown, std::vector<ViewRequest>& views, episode::LookalikeAid aid, bool numbered) {
  for (ViewRequest& v : views) {
    if (v.view != ViewKind::kItem) continue;
    v.number = std::max(0, held_number);
    v.caption = held_number > 0
                    ? "The object in your hand, number " + std::to_string(held_number) + " where you picked it up."
                    : "The object in your hand.";
  }
  if (s.phase == episode::Phase::kDone || aid == episode::LookalikeAid::kWords) return;
  const std::map<std::string, int> labels = tasks::close_up_labels(lookalikes);
  for (const tasks::Identification& id : lookalikes) {
    const graph::ObjectId object = g.find_object(id.object);
    if (!object.valid() || object == s.held) continue;
    // An item the agent has moved: the words named it where it stood, and showing it again would
    // only tell the agent where it put it.
    if (id.role == "item" && s.objects[object].position != g.objects[object].X_WO.translation()) continue;
    const graph::PlatformId platform = episode::furniture_platform_of(g, s, object);
    if (!platform.valid()) continue;
    const bool at_start = s.steps == 0;
    const bool here = s.at_platform == platform;
    if (!at_start && !here) continue;
    const int side = here && s.side >= 0 ? s.side : std::max(0, g.platforms[platform].default_side);
    // The paper's aid for finding the object, not its answer: no number unless the run asks for
    // the assisted variant (then shown afresh whenever the number changed).
    const int number = numbered ? episode::number_of(g, s, object) : 0;
    const std::string seen = g.platforms[platform].name + "|" + std::to_string(side) + "|" + std::to_string(number);
    std::string& last = shown.last[id.object];
    if (last == seen) continue;
    last = seen;
    ViewRequest v;
    v.view = ViewKind::kFocus;
    v.object = object;
    v.width = width;
    v.height = height;
    v.number = number;
    const std::string where = here ? "here" : "on " + g.platforms[platform].name;
    const std::string called = aid == episode::LookalikeAid::kImage
                                   ? "Close-up " + std::to_string(labels.at(id.object)) + ": the " + id.reference.noun +
                                         " the task means"
                                   : "The object the task calls '" + id.phrase + "'";
    v.caption = called +
                (number > 0 ? ", object " + std::to_string(number) + " " + where + " as it stands now"
                            : ", where it stands " + where) +
                ", seen from where you " + (here ? "stand" : "arrive") + "; every other object faded.";
    views.push_back(std::move(v));
  }
}

}  // namespace mtg::render
