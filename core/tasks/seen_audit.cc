#include "core/tasks/seen_audit.h"

#include <algorithm>
#include <optional>

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
// readable place (in a picture or a zoom of it). Its pictures are drawn when first asked about,
// as the generator's are: most questions are settled by the first.
constexpr std::size_t kRememberedViews = 2048;

struct SeenAudit::View {
  episode::WorldState state;
  graph::PlatformId platform;
  int side = 0;
  std::vector<render::PlatformPicture> pictures;
  std::vector<std::optional<render::IdView>> ids;  // one per picture, once drawn
  std::shared_ptr<const render::ViewSight> sight;
  std::vector<std::optional<std::vector<graph::ObjectId>>> readable;  // per picture, once laid out
};

SeenAudit::SeenAudit(const graph::SceneGraph& g, const render::SceneGeometry& geometry, TaskOptions options)
    : g_(g), geometry_(geometry), options_(std::move(options)) {
  MTG_DEMAND(options_.visibility.has_value(), "seen audit: the task options have no visibility rules");
}

const render::IdView& SeenAudit::ids(View& v, std::size_t k) const {
  if (!v.ids[k]) {
    const render::VisibilityOptions& vo = *options_.visibility;
    const render::Camera pass = render::at_resolution(v.pictures[k].camera, vo.pass_width(), vo.pass_height());
    v.ids[k] = render::draw_id_view_of(g_, geometry_, v.state, pass, episode::everything_on(g_, v.state, v.platform));
  }
  return *v.ids[k];
}

std::shared_ptr<SeenAudit::View> SeenAudit::view(const episode::WorldState& s, graph::PlatformId platform) const {
  // Remembered by everything the picture can depend on: every object's place, what is held.
  std::string key;
  append_key(key, platform.value());
  append_key(key, s.held.value());
  for (const graph::ObjectId o : g_.objects.ids()) {
    append_key(key, s.objects[o].position.x());
    append_key(key, s.objects[o].position.y());
    append_key(key, s.objects[o].position.z());
  }
  for (const graph::ObjectId o : episode::numbered_on(g_, s, platform)) append_key(key, o.value());
  if (const auto it = views_.find(key); it != views_.end()) return it->second;
  // Views of states no later task starts from are many (a Level 3 set holds thousands): the
  // remembered ones are forgotten when they fill the table (drawn again when asked).
  if (views_.size() >= kRememberedViews) views_.clear();
  auto& slot = views_[key];
  const render::VisibilityOptions& vo = *options_.visibility;
  auto v = std::make_shared<View>();
  v->state = s;
  v->platform = platform;
  v->side = std::max(0, g_.platforms[platform].default_side);
  v->pictures = render::platform_pictures(g_, s, platform, v->side, vo.image_width, vo.image_height);
  v->ids.resize(v->pictures.size());
  v->readable.resize(v->pictures.size());
  std::vector<render::Camera> cameras;
  std::vector<render::ViewSight::Count> counts;
  View* raw = v.get();
  for (std::size_t k = 0; k < v->pictures.size(); ++k) {
    cameras.push_back(v->pictures[k].camera);
    counts.push_back([this, raw, k] { return std::make_shared<const std::vector<render::ObjectSight>>(ids(*raw, k).objects); });
  }
  v->sight = std::make_shared<const render::ViewSight>(std::move(cameras), std::move(counts), vo);
  slot = v;
  ++drawn_;
  return v;
}

bool SeenAudit::readable(View& v, graph::ObjectId o, std::vector<std::string>& problems) const {
  // The pass holds every numbered object's pixels as a whole pass has them (they are on the
  // platform), so the marks go where the renderer puts them; each picture's layout is checked
  // against the rules as it is laid out.
  const std::vector<render::ItemMark> all_items = render::item_marks(g_, v.state, v.platform);
  for (std::size_t k = 0; k < v.pictures.size(); ++k) {
    if (!v.readable[k]) {
      const std::vector<render::ItemMark> items = render::numbered_in(g_, v.state, v.platform, v.side, v.pictures[k],
                                                                      all_items, render::showing_in(v.sight->objects(k)));
      const render::ItemMarksPlan marks =
          render::plan_item_marks(g_, geometry_, v.state, v.pictures[k].camera, items, {}, ids(v, k).image);
      std::vector<graph::ObjectId>& placed = v.readable[k].emplace();
      for (const render::ItemMark& m : items) {
        if (marks.placed(m.number)) placed.push_back(m.object);
      }
      v.ids[k]->image = {};  // laid out: its pixels are not needed again (its counts are kept)
      for (const std::string& p : marks.problems()) {
        problems.push_back("marks at " + g_.platforms[v.platform].name + (k == 0 ? "" : " (" + render::part_words(v.pictures[k]) + ")") + ": " + p);
      }
    }
    if (std::find(v.readable[k]->begin(), v.readable[k]->end(), o) != v.readable[k]->end()) return true;
  }
  return false;
}

std::vector<std::string> SeenAudit::check(const Task& task) const {
  std::vector<std::string> problems;
  auto fail = [&](const std::string& what) { problems.push_back(task.id + ": " + what); };
  const episode::TaskGoal goal = episode::task_goal_from_json(g_, task.goal);
  const double min_gap = options_.visibility->min_gap;
  auto clearly = [&](const View& v, graph::ObjectId o) { return v.sight->clearly_visible(o); };
  auto readable = [&](View& v, graph::ObjectId o) {
    std::vector<std::string> layout_problems;
    const bool ok = this->readable(v, o, layout_problems);
    for (const std::string& p : layout_problems) fail(p);
    return ok;
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
          const std::shared_ptr<View> held = view(initial, platform);  // a later view() may forget it
          View& v = *held;
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
    const std::shared_ptr<View> source_view = view(start, part.source);
    View& source = *source_view;
    named(which, start, part.source, part.item, source);
    if (!readable(source, part.item)) fail(which + "the item's number has no readable place in the marked view");
    if (!part.anchor.valid()) continue;
    const episode::WorldState holding = start_of_part(g_, task, options_, static_cast<int>(k), true);
    const std::shared_ptr<View> destination = view(holding, part.platform);
    for (const graph::ObjectId a : part.anchors()) named(which + "anchor ", holding, part.platform, a, *destination);
  }
  return problems;
}

}  // namespace mtg::tasks
