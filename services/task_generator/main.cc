// Task-generator service: answers task_set_request_t on MTG_TASKSET_REQ with a generated task
// database and a task_set_summary_t on MTG_TASKSET_SUMMARY (same request_id). Failures are
// replied to with ok = false and a one-line error; the service keeps serving.

#include <CLI/CLI.hpp>

#include <deque>

#include "bus/bus.h"
#include "bus/channels.h"
#include "bus/process/service_loop.h"
#include "bus/url.h"
#include "core/tasks/generator.h"
#include "core/tasks/job.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "core/util/parallel.h"
#include "mtg/task_set_request_t.hpp"
#include "mtg/task_set_summary_t.hpp"

int main(int argc, char** argv) {
  CLI::App app{"mtg task-generator service"};
  std::string url = mtg::bus::default_url();
  std::string data_dir, profile = "replica_cad";
  app.add_option("--url", url, "LCM URL");
  app.add_option("--data", data_dir, "dataset root (requests may override)");
  app.add_option("--profile", profile, "scene profile");
  CLI11_PARSE(app, argc, argv);
  mtg::log::set_role("task_generator");
  mtg::process::install_stop_signals();
  try {
    mtg::bus::Bus bus(url);
    mtg::bus::HeaderStamper stamp("", mtg::process::sender_id("task_generator"));
    mtg::process::ServiceLoop loop(bus, stamp, "task_generator");
    std::deque<mtg::task_set_request_t> queue;
    bus.subscribe<mtg::task_set_request_t>(mtg::bus::kTaskSetRequest,
                                           [&](const std::string&, const mtg::task_set_request_t& r) { queue.push_back(r); });
    mtg::log::info("ready on " + url);
    loop.run([&] {
      while (!queue.empty()) {
        const mtg::task_set_request_t req = queue.front();
        queue.pop_front();
        mtg::task_set_summary_t reply{};
        reply.request_id = req.request_id;
        reply.scene = req.scene;
        reply.seed = req.seed;
        reply.db_path = req.out_path;
        reply.generator_version = mtg::tasks::kGeneratorVersion;
        try {
          mtg::tasks::GenerationJob job;
          job.scenes = {req.scene};
          job.data_dir = req.data_dir.empty() ? data_dir : req.data_dir;
          job.profile = profile;
          job.out = req.out_path;
          job.options.seed = static_cast<std::uint64_t>(req.seed);
          if (!req.levels.empty()) job.options.levels = mtg::tasks::parse_levels(req.levels);
          if (!req.config_json.empty()) {
            nlohmann::json overrides;
            try {
              overrides = nlohmann::json::parse(req.config_json);
            } catch (const nlohmann::json::exception&) {
              throw mtg::Error("task_set_request " + req.request_id + ": config_json is not JSON");
            }
            mtg::tasks::apply_overrides(job, overrides);
          }
          loop.set_in_flight(1);
          job.jobs = mtg::default_jobs();
          const auto report = mtg::tasks::run_generation(job);
          for (int l = 0; l < 4; ++l) reply.level_counts[l] = static_cast<int32_t>(report.levels[static_cast<size_t>(l)]);
          reply.total = report.total;
          reply.config_hash = job.options.config_hash();
          reply.ok = true;
          mtg::log::info("task set " + req.request_id + ": " + std::to_string(report.total) + " tasks -> " + req.out_path);
        } catch (const std::exception& e) {
          reply.ok = false;
          reply.error = e.what();
          mtg::log::error("task set " + req.request_id + ": " + reply.error);
        }
        loop.set_in_flight(0);
        reply.header = stamp.next({}, 0, "taskset");
        bus.publish(mtg::bus::kTaskSetSummary, reply);
      }
    });
  } catch (const std::exception& e) {
    mtg::log::error(e.what());
    return 1;
  }
  return 0;
}
