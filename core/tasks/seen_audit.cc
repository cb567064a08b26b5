#include "core/tasks/seen_audit.h"

#include <algorithm>

#include "core/episode/goals.h"
#include "core/render/mark_layout.h"
#include "core/render/view.h"
#include "core/render/visibility.h"
#include "core/tasks/referring.h"
#include "core/tasks/validate.h"
#include "core/util/error.h"
#include "core/util/memo_table.h"

namespace mtg::tasks {

// One arrival view drawn afresh: what it shows of the platform's objects, and whose number has a
// readable place (in the picture or a zoom).
struct SeenAudit::View {
  std::vector<render::PlatformPicture> pictures;
  std::vector<render::IdImage> passes;  // one per picture
  int side = 0;
  std::shared_ptr<const render::ViewSight> sight;
  bool marks_laid_out = false;
  std::vector<graph::ObjectId> readable;
  std::vector<std::string> mark_problems;
};

SeenAudit::SeenAudit(const graph::SceneGraph& g, const render::SceneGeometry& geometry, TaskOptions options)
    : g_(g), geometry_(geometry), options_(std::move(options)) {
  MTG_DEMAND(options_.visibility.has_value(), "seen audit: the task options have no visibility rules");
}

SeenAudit::View& SeenAudit::view(const episode::WorldState& s, graph::PlatformId platform) const {
  // Remembered by everything the picture can depend on: every object's place, what is held.
  std::string key;
  append_key(key, platform.value());
  append_key(key, s.held.value());
  for (const graph::ObjectId o : g_.objects.ids()) {
    append_key(key, s.objects[o].position.x());
    append_key(key, s.objects[o].position.y());
    append_key(key, s.objects[o].position.z());
  }
  for (const graph::ObjectId o : episode::pickable_on(g_, s, platform)) append_key(key, o.value());
  auto& slot = views_[key];
  if (slot) return *slot;
  const render::VisibilityOptions& vo = *options_.visibility;
  auto v = std::make_shared<View>();
  v->side = std::max(0, g_.platforms[platform].default_side);
  v->pictures = render::platform_pictures(g_, s, platform, v->side, vo.image_width, vo.image_height);
  const std::vector<graph::ObjectId> on = episode::everything_on(g_, s, platform);
  std::vector<render::ViewSight::Picture> pictures;
  for (const render::PlatformPicture& picture : v->pictures) {
    const render::Camera pass = render::at_resolution(picture.camera, vo.pass_width(), vo.pass_height());
    render::IdView ids = render::draw_id_view_of(g_, geometry_, s, pass, on);
    pictures.push_back({picture.camera, std::move(ids.objects)});
    v->passes.push_back(std::move(ids.image));
  }
  v->sight = std::make_shared<const render::ViewSight>(std::move(pictures), vo);
  slot = std::move(v);
  return *slot;
}

void SeenAudit::lay_out_marks(View& v, const episode::WorldState& s, graph::PlatformId platform) const {
  if (v.marks_laid_out) return;
  v.marks_laid_out = true;
  // The pass holds every numbered object's pixels as a whole pass has them (they are on the
  // platform), so the marks go where the renderer puts them.
  const std::vector<render::ItemMark> all_items = render::item_marks(g_, s, platform);
  for (std::size_t k = 0; k < v.pictures.size(); ++k) {
    std::vector<graph::ObjectId> showing;
    for (const render::ObjectSight& o : v.sight->objects(k)) {
      if (o.visible > 0) showing.push_back(graph::ObjectId::of_index(static_cast<std::size_t>(o.object)));
    }
    const std::vector<render::ItemMark> items =
        render::numbered_in(g_, s, platform, v.side, v.pictures[k], all_items, showing);
    const render::ItemMarksPlan marks =
        render::plan_item_marks(g_, geometry_, s, v.pictures[k].camera, items, {}, v.passes[k]);
    for (const render::ItemMark& m : items) {
      if (marks.placed(m.number) &&
          std::find(v.readable.begin(), v.readable.end(), m.object) == v.readable.end()) {
        v.readable.push_back(m.object);
      }
    }
    for (const std::string& p : marks.problems()) {
      v.mark_problems.push_back(k == 0 ? p : render::part_words(v.pictures[k]) + ": " + p);
    }
  }
  v.passes.clear();  // not needed again
}

std::vector<std::string> SeenAudit::check(const Task& task) const {
  std::vector<std::string> problems;
  auto fail = [&](const std::string& what) { problems.push_back(task.id + ": " + what); };
  const episode::TaskGoal goal = episode::task_goal_from_json(g_, task.goal);
  const double min_gap = options_.visibility->min_gap;
  auto clearly = [&](const View& v, graph::ObjectId o) { return v.sight->clearly_visible(o); };
  auto readable = [&](const View& v, graph::ObjectId o) {
    return std::find(v.readable.begin(), v.readable.end(), o) != v.readable.end();
  };
  int part_index = 0;  // the part whose objects are being named
  auto named = [&](const std::string& which, const episode::WorldState& s, graph::PlatformId platform,
                   graph::ObjectId o, const View& v) {
    if (!clearly(v, o)) {
      fail(which + g_.objects[o].name + " is not clearly visible from where the agent arrives at " +
           g_.platforms[platform].name + " (" + std::to_string(static_cast<long>(v.sight->image_pixels(o))) + " px, " +
           std::to_string(static_cast<int>(100 * v.sight->of(o).share())) + " % of it)");
    }
    for (const Identification& id : task.identify) {
      if (id.part != part_index || id.object != g_.objects[o].name || id.platform != g_.platforms[platform].name) continue;
      if (!seen_as(g_, s, platform, o, id.reference, options_.ambiguity, v.sight, min_gap)) {
        fail(which + "'" + id.phrase + "' counts or relates objects the view does not show as it says");
      }
    }
  };
  if (goal.is_outcome) {
    const episode::WorldState initial = episode::initial_state(g_);
    for (const episode::SetPredicate& p : goal.outcome.all) {
      for (const auto* list : {&p.objects, &p.objects2}) {
        for (const graph::ObjectId o : *list) {
          const graph::PlatformId platform = episode::furniture_platform_of(g_, initial, o);
          if (!platform.valid()) continue;
          View& v = view(initial, platform);
          lay_out_marks(v, initial, platform);
          if (!clearly(v, o)) fail(g_.objects[o].name + " is not clearly visible where it stands");
          if (!readable(v, o)) fail(g_.objects[o].name + " has no readable number where it stands");
        }
      }
    }
    return problems;
  }
  for (std::size_t k = 0; k < goal.parts.size(); ++k) {
    const episode::AtomicGoal& part = goal.parts[k];
    const std::string which = "part " + std::to_string(k) + ": ";
    part_index = static_cast<int>(k);
    const episode::WorldState start = start_of_part(g_, task, options_, static_cast<int>(k), false);
    View& source = view(start, part.source);
    lay_out_marks(source, start, part.source);
    named(which, start, part.source, part.item, source);
    if (!readable(source, part.item)) fail(which + "the item's number has no readable place in the marked view");
    for (const std::string& p : source.mark_problems) fail(which + "marks at " + g_.platforms[part.source].name + ": " + p);
    if (!part.anchor.valid()) continue;
    const episode::WorldState holding = start_of_part(g_, task, options_, static_cast<int>(k), true);
    const View& destination = view(holding, part.platform);
    for (const graph::ObjectId a : part.anchors()) named(which + "anchor ", holding, part.platform, a, destination);
  }
  return problems;
}

}  // namespace mtg::tasks
