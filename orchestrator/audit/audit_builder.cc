#include "orchestrator/audit/audit_builder.h"

#include <filesystem>
#include <fstream>
#include <map>

#include "core/episode/rules.h"
#include "core/render/close_ups.h"
#include "core/render/image_renderer.h"
#include "core/tasks/audit_plan.h"
#include "core/tasks/lookalike_aid.h"
#include "core/tasks/task_db.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/hash.h"
#include "orchestrator/audit/audit_store.h"

namespace mtg::orchestrator::audit {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::map<std::string, std::string> audit_meta(const AuditOptions& o, const json& config) {
  std::map<std::string, std::string> meta = {{"format", kAuditFormat},
          {"tasks", fs::absolute(o.tasks).lexically_normal().string()},
          {"config_hash", to_hex(fnv1a64(config.dump()))},
          {"per_level", std::to_string(o.per_level)},
          {"seed", std::to_string(o.seed)},
          {"scene", o.scene},
          {"image_size", std::to_string(o.width) + "x" + std::to_string(o.height)},
          {"names", o.names ? "on" : "off"}};
  // Only where it is not the default: audits made before the aid was a choice stay this audit.
  if (o.lookalike_aid != "both") meta["lookalike_aid"] = o.lookalike_aid;
  return meta;
}

render::ViewSpec spec_of(const graph::SceneGraph& g, const render::ViewRequest& v) {
  render::ViewSpec s;
  s.view = v.view;
  if (v.platform.valid()) s.platform = g.platforms[v.platform].name;
  s.side = v.side;
  if (v.object.valid()) s.item = g.objects[v.object].name;
  s.marks = v.marks;
  s.number = v.number;
  s.caption = v.caption;
  return s;
}

}  // namespace

int build_audit(const AuditOptions& o, std::ostream& progress, bool redraw) {
  if (o.tasks.empty()) throw Error("mtg audit: --tasks <task database> or --suite <suite file> is required");
  if (o.out.empty()) throw Error("mtg audit: --out <folder> is required");
  if (o.per_level < 1) throw Error("mtg audit: --per-level must be at least 1");
  const json config = tasks::read_generator_config(o.tasks);
  tasks::TaskOptions options;
  if (config.contains("ambiguity")) options.ambiguity = tasks::ambiguity_from_string(config["ambiguity"].get<std::string>());
  options.rules.object_names = o.names;
  const episode::LookalikeAid aid = episode::lookalike_aid_from_string(o.lookalike_aid, "mtg audit: --lookalike-aid");
  options.rules.lookalike_aid = aid;
  const std::string task_format = tasks::read_task_set_meta(o.tasks, "generator_version").value_or(std::string());
  options.rules.numbering = tasks::numbering_of_format(task_format);
  const std::map<std::string, std::string> meta = audit_meta(o, config);

  fs::create_directories(fs::path(o.out) / "images");
  AuditStore store(o.out, true);
  const std::map<std::string, std::string> had = store.meta();
  const std::vector<tasks::Task> all = tasks::read_tasks(o.tasks);
  const std::vector<const tasks::Task*> sample = tasks::sample_for_audit(all, o.per_level, o.seed, o.scene);
  if (sample.empty()) throw Error("mtg audit: " + o.tasks + " has no task" + (o.scene.empty() ? "" : " of scene " + o.scene));
  if (!had.empty()) {
    for (const auto& [key, value] : meta) {
      const auto it = had.find(key);
      if (it == had.end() || it->second != value) {
        throw Error("mtg audit: " + o.out + " holds an audit of other inputs (" + key + ": " +
                    (it == had.end() ? "none" : it->second) + ", not " + value + "); give another --out");
      }
    }
    if (static_cast<int>(store.items().size()) == static_cast<int>(sample.size())) {
      progress << "audit: " << o.out << " holds these " << sample.size() << " tasks already; answers kept\n";
      return static_cast<int>(sample.size());
    }
  }
  render::ImageRenderer renderer(o.profile, {}, -1, tasks::platform_rules_of_format(task_format));
  for (std::size_t i = 0; i < sample.size(); ++i) {
    const tasks::Task& task = *sample[i];
    const graph::SceneCache::Entry& entry = renderer.scenes().load(task.scene, o.data_dir);
    const graph::SceneGraph& g = entry.graph;
    episode::RuleOptions rules = options.rules;
    rules.step_limit = task.step_limit;
    const tasks::AuditPlan plan = tasks::plan_audit(g, task, options);
    // The look-alike close-ups as a run's observations would send them: the memory of what was
    // shown runs through every step, though only the arrivals are kept.
    render::CloseUpsShown shown;
    std::vector<std::vector<render::ViewRequest>> views_at(plan.steps.size());
    for (std::size_t k = 0; k < plan.steps.size(); ++k) {
      const episode::WorldState& s = plan.steps[k].state;
      views_at[k] = render::observation_views(s, o.width, o.height, rules.min_region_size);
      // Without the held item's number: it would answer a question asked earlier in the page.
      render::add_close_ups(g, s, task.identify, 0, o.width, o.height, shown, views_at[k], aid);
    }
    const tasks::TaskWords words = tasks::task_words(task.id, task.text, task.identify, aid, true);
    json observations = json::array();
    for (std::size_t k = 0; k < plan.observations.size(); ++k) {
      const tasks::AuditObservation& ob = plan.observations[k];
      render::ImageRequest request;
      request.scene = task.scene;
      request.data_dir = o.data_dir;
      request.width = o.width;
      request.height = o.height;
      request.state = episode::state_delta(g, ob.state);
      request.min_region_size = rules.min_region_size;
      for (const render::ViewRequest& v : views_at[static_cast<std::size_t>(ob.step)]) request.views.push_back(spec_of(g, v));
      json images = json::array();
      if (!request.views.empty()) {
        const render::ImageReply reply = renderer.render(request);
        for (std::size_t m = 0; m < reply.images.size(); ++m) {
          const render::EncodedImage& img = reply.images[m];
          const std::string name = std::to_string(i) + "_" + std::to_string(k) + "_" + std::to_string(m) + ".png";
          write_file_atomically(fs::path(o.out) / "images" / name, [&](std::ostream& os) {
            os.write(reinterpret_cast<const char*>(img.bytes.data()), static_cast<std::streamsize>(img.bytes.size()));
          });
          images.push_back({{"role", img.role}, {"caption", img.caption}, {"width", img.width},
                            {"height", img.height}, {"url", "/api/audit/images/" + name}});
        }
      }
      json actions = json::array();
      for (const episode::ActionOption& a : episode::action_space(g, ob.state, rules)) {
        actions.push_back({{"key", a.key}, {"description", a.description}});
      }
      observations.push_back({{"title", ob.title},
                              {"text", episode::observation_text(g, ob.state, rules)},
                              {"hint", k == 0 ? words.hint : std::string()},
                              {"actions", actions},
                              {"images", images}});
    }
    json questions = json::array(), truth = json::object();
    for (const tasks::AuditQuestion& q : plan.questions) {
      questions.push_back({{"id", q.id}, {"ask", q.ask}, {"observation", q.observation}});
      truth[q.id] = q.truth;
    }
    Item item;
    item.index = static_cast<int>(i);
    item.task_id = task.id;
    item.level = task.level;
    item.page = {{"index", i}, {"task_id", task.id}, {"level", task.level}, {"task_text", words.text},
                 {"observations", observations}, {"questions", questions}};
    item.truth = truth;
    store.add_item(item);
    // A terminal redraws one line; a log gets a line per tenth, not one line of carriage returns.
    const std::size_t n = sample.size();
    if (redraw) {
      progress << "\raudit: " << (i + 1) << "/" << n << " tasks prepared" << std::flush;
    } else if ((i + 1) * 10 / n != i * 10 / n || i + 1 == n) {
      progress << "audit: " << (i + 1) << "/" << n << " tasks prepared\n" << std::flush;
    }
  }
  if (redraw) progress << "\n";
  store.set_meta(meta);
  return static_cast<int>(sample.size());
}

}  // namespace mtg::orchestrator::audit
