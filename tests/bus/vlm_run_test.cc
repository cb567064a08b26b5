// Model agents end to end: `mtg run` with real adapter processes against a local server that
// plays a scripted model in all three wire formats, with images; a rerun from the cache makes no
// HTTP call and gives the same verdicts; the key never reaches the run folder; a rejected key
// stops the run with a clear message; and the rate governor holds two processes to one budget.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "agents/vlm/cost_estimate.h"
#include "agents/vlm/model_spec.h"
#include "bus/url.h"
#include "core/tasks/generator.h"
#include "core/tasks/task_db.h"
#include "orchestrator/run/results_db.h"
#include "orchestrator/run/run_estimate.h"
#include "orchestrator/run/run_plan.h"
#include "tests/support/fake_model_server.h"
#include "tests/support/graph_fixtures.h"
#include "tests/support/browser.h"
#include "tests/support/process.h"
#include "tests/support/text_file.h"

// Last: httplib.h brings in <resolv.h>, whose `_res` macro breaks Eigen's headers.
#include <httplib.h>

namespace mtg {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::Behaviour;

constexpr const char* kKey = "sk-test-SECRET-b7f3e9-DO-NOT-LEAK";

class VlmRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    built_ = testing::render_room(fx_);
    tasks::TaskOptions options;
    options.levels = {1};
    const auto generated = tasks::generate_tasks(built_.scene, built_.graph, options);
    db_ = (fx_.root() / "tasks.sqlite").string();
    tasks::write_task_db(db_, {generated.set}, generated.votes, options);
    std::map<std::string, std::vector<std::string>> plans;
    for (const auto& t : generated.set.tasks) plans.emplace(t.text, t.oracle);
    server_.set_model(testing::oracle_model(plans));
    // Children inherit the environment: the keys, the servers' addresses, a private cache.
    ::setenv("OPENAI_API_KEY", kKey, 1);
    ::setenv("ANTHROPIC_API_KEY", kKey, 1);
    ::setenv("GEMINI_API_KEY", kKey, 1);
    ::setenv("OPENAI_BASE_URL", (server_.url() + "/v1").c_str(), 1);
    ::setenv("ANTHROPIC_BASE_URL", server_.url().c_str(), 1);
    ::setenv("GEMINI_BASE_URL", server_.url().c_str(), 1);
    ::setenv("MTG_CACHE_DIR", (fx_.root() / "cache").c_str(), 1);
  }

  int mtg_run(const std::string& out, const std::vector<std::string>& agents, const std::vector<std::string>& extra,
              int limit = 3, int parallel = 3) {
    std::vector<std::string> args = {testing::bin("mtg"), "run", "--tasks", db_, "--limit", std::to_string(limit),
                                     "--parallel", std::to_string(parallel), "--image-size", "320x240", "--out", (fx_.root() / out).string(),
                                     "--data", fx_.root().string(), "--profile", "none", "--no-progress",
                                     "--episode-timeout", "60"};
    for (const auto& a : agents) args.insert(args.end(), {"--agent", a});
    args.insert(args.end(), extra.begin(), extra.end());
    testing::ChildProcess p(args, (fx_.root() / (out + ".log")).string());
    return p.wait(240000);
  }

  // `mtg view` on the run gives, for every step of every episode, the request the server saw:
  // the same system text, turns in order with the same texts, the same images per turn; and a
  // browser shows it with its images.
  void expect_the_viewer_shows_each_request_as_sent(const std::vector<testing::SeenRequest>& seen) {
    using nlohmann::json;
    std::multiset<std::string> sent;  // what the server saw, one fingerprint per request
    auto fingerprint = [](const std::string& provider, const std::string& system,
                          const std::vector<std::pair<std::string, std::string>>& turns, int images, int last) {
      return json({provider, system, turns, images, last}).dump();
    };
    for (const auto& r : seen) {
      sent.insert(fingerprint(r.chat.provider, r.chat.system, r.chat.turns, r.chat.images, r.chat.last_turn_images));
    }
    testing::ChildProcess view({testing::bin("mtg"), "view", (fx_.root() / "run").string(), "--port", "0"},
                               (fx_.root() / "view.log").string());
    const int port = testing::port_in_log((fx_.root() / "view.log").string(), 10000);
    ASSERT_GT(port, 0) << testing::read_text(fx_.root() / "view.log");
    httplib::Client http("127.0.0.1", port);
    const auto list = http.Get("/api/runs/run/episodes?limit=100");
    ASSERT_TRUE(list && list->status == 200);
    const json rows = json::parse(list->body)["rows"];
    ASSERT_FALSE(rows.empty()) << list->body;
    std::multiset<std::string> shown;
    int with_images = 0;
    std::string an_episode;
    for (const auto& row : rows) {
      const std::string id = std::to_string(row["episode_id"].get<long long>());
      const auto got = http.Get("/api/runs/run/episodes/" + id);
      ASSERT_TRUE(got && got->status == 200) << id;
      const json episode = json::parse(got->body);
      for (const auto& step : episode["steps"]) {
        if (step["action"].is_null()) continue;
        ASSERT_TRUE(step["request"].is_object()) << "episode " << id << " step " << step["step"];
        std::string system;
        std::vector<std::pair<std::string, std::string>> turns;
        int images = 0, last = 0;
        for (const auto& m : step["request"]["messages"]) {
          ASSERT_TRUE(m["text"].is_string()) << m.dump();
          if (m["role"] == "system") {
            system = m["text"];
            continue;
          }
          turns.emplace_back(m["role"], m["text"]);
          last = static_cast<int>(m["images"].size());
          images += last;
          for (const auto& img : m["images"]) with_images += img["url"].is_string() ? 1 : 0;
        }
        const std::string provider = step["action"]["provider"];
        const auto it = shown.insert(fingerprint(provider, system, turns, images, last));
        EXPECT_TRUE(sent.count(*it)) << "episode " << id << " step " << step["step"] << ": not a request the server saw";
        EXPECT_EQ(step["reply"]["text"], step["action"]["raw_reply"]);
        if (provider == "openai") an_episode = id;
      }
    }
    EXPECT_TRUE(shown == sent) << "every request the server saw, each once: " << shown.size() << " shown, "
                               << sent.size() << " sent";
    EXPECT_GT(with_images, 0);

    if (testing::HeadlessBrowser::executable().empty()) return;
    testing::HeadlessBrowser b(fx_.root() / "chromium-profile");
    b.navigate("http://127.0.0.1:" + std::to_string(port) + "/#/run/run/episode/" + an_episode);
    ASSERT_TRUE(b.wait_for("document.querySelectorAll('details.request').length > 1", 20000));
    // The second step's request: its question with the platform view, the first step's turns before it.
    b.evaluate("(() => { const d = document.querySelectorAll('details.request')[1]; d.open = true; "
               "d.scrollIntoView(); })()");
    ASSERT_TRUE(b.wait_for("(() => { const i = [...document.querySelectorAll('details.request')[1]"
                           ".querySelectorAll('img')]; return i.length > 0 && i.every((x) => x.complete && "
                           "x.naturalWidth > 0); })()", 20000));
    EXPECT_EQ(b.evaluate("document.querySelectorAll('details.request')[1].querySelectorAll('.msg').length").get<int>(),
              4) << "system, step 1's question and answer, step 2's question";
    const std::string summary = b.evaluate("document.querySelector('details.request summary').textContent");
    EXPECT_THAT(summary, HasSubstr("prompts v3+"));
    EXPECT_THAT(b.evaluate("document.querySelector('.usage').textContent").get<std::string>(), HasSubstr("tokens"));
    b.screenshot(fs::path(MTG_ARTIFACT_DIR) / "view" / "model-request.png", true);
  }

  testing::FixtureDataset fx_;
  testing::BuiltScene built_;
  std::string db_;
  testing::FakeModelServer server_;
};

TEST_F(VlmRunTest, ThreeProvidersPlayWholeEpisodesAndACachedRerunCallsNobody) {
  const std::vector<std::string> agents = {"openai:gpt-4o", "anthropic:claude-3-5-haiku-20241022",
                                           "gemini:gemini-2.0-flash"};
  ASSERT_EQ(mtg_run("run", agents, {}), 0) << testing::read_text(fx_.root() / "run.log");
  const auto rows = orchestrator::read_results(fx_.root() / "run" / "results.sqlite");
  ASSERT_EQ(rows.size(), 9u);
  for (const auto& r : rows) {
    EXPECT_TRUE(r.success) << r.agent << " " << r.task_id << ": " << r.detail;
    EXPECT_EQ(r.usage.model_calls, r.steps) << "one call per step";
    EXPECT_EQ(r.usage.cache_hits, 0);
    EXPECT_GT(r.usage.images_sent, 0);
    EXPECT_GT(r.usage.input_tokens, 0);
    EXPECT_THAT(r.usage.prompt_version, ::testing::StartsWith("v3+"));
  }
  const auto seen = server_.requests();
  std::set<std::string> providers;
  for (const auto& s : seen) {
    providers.insert(s.chat.provider);
    EXPECT_GT(s.chat.last_turn_images, 0) << "every step's question carries its images";
    const bool keyed = (s.headers.count("authorization") && s.headers.at("authorization") == std::string("Bearer ") + kKey) ||
                       (s.headers.count("x-api-key") && s.headers.at("x-api-key") == kKey) ||
                       (s.headers.count("x-goog-api-key") && s.headers.at("x-goog-api-key") == kKey);
    EXPECT_TRUE(keyed) << s.path;
  }
  EXPECT_EQ(providers, (std::set<std::string>{"openai", "anthropic", "gemini"}));
  expect_the_viewer_shows_each_request_as_sent(seen);

  // The key is nowhere in what the run wrote: recording, logs, results, plan, reports.
  for (const auto& entry : fs::recursive_directory_iterator(fx_.root() / "run")) {
    if (entry.is_regular_file()) {
      EXPECT_EQ(testing::read_text(entry.path()).find(kKey), std::string::npos) << "the API key leaked into " << entry.path();
    }
  }
  EXPECT_EQ(testing::read_text(fx_.root() / "run.log").find(kKey), std::string::npos);

  // A rerun answers from the cache alone: no HTTP call, the same verdicts, nothing spent.
  const std::size_t calls = seen.size();
  ASSERT_EQ(mtg_run("rerun", agents, {"--cache-only"}), 0) << testing::read_text(fx_.root() / "rerun.log");
  EXPECT_EQ(server_.requests().size(), calls);
  const auto again = orchestrator::read_results(fx_.root() / "rerun" / "results.sqlite");
  ASSERT_EQ(again.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(orchestrator::verdict_fingerprint(again[i]), orchestrator::verdict_fingerprint(rows[i]));
    EXPECT_EQ(again[i].usage.cache_hits, again[i].usage.model_calls);
    EXPECT_EQ(again[i].usage.input_tokens, rows[i].usage.input_tokens);
    EXPECT_DOUBLE_EQ(again[i].usage.cost_usd, rows[i].usage.cost_usd);
    EXPECT_EQ(again[i].usage.spent_usd, 0.0);
  }
}

TEST_F(VlmRunTest, ARejectedKeyStopsTheAgentWithAClearMessageAndScoresNothing) {
  server_.script(std::vector<Behaviour>(
      20, Behaviour{Behaviour::Kind::kStatus, 401,
                    std::string(R"({"error":{"message":"Incorrect API key provided: )") + kKey + R"(","code":"invalid_api_key"}})",
                    {}, 0, ""}));
  EXPECT_EQ(mtg_run("denied", {"openai:gpt-4o"}, {"--no-render"}), 1);
  const std::string log = testing::read_text(fx_.root() / "denied.log");
  EXPECT_THAT(log, HasSubstr("authentication failed"));
  EXPECT_THAT(log, HasSubstr("run the same command again to resume"));
  EXPECT_EQ(log.find(kKey), std::string::npos) << "the server echoed the key; the adapter must redact it";
  EXPECT_TRUE(orchestrator::read_results(fx_.root() / "denied" / "results.sqlite").empty())
      << "a rejected key is not the model's failure";
  EXPECT_LE(server_.requests().size(), 3u) << "no retries after 401 (one call per episode in flight at most)";
}

TEST_F(VlmRunTest, TheGovernorHoldsTwoProcessesToOneBudget) {
  // 8 calls per 2 s window between them; the server itself answers 429 beyond 8 per 2 s.
  server_.enforce_limit(8, std::chrono::milliseconds(2000));
  testing::ChildProcess governor({testing::bin("mtg_governor"), "--url", bus::kDefaultUrl},
                                 (fx_.root() / "governor.log").string());
  auto asker = [&](const std::string& name) {
    return std::make_unique<testing::ChildProcess>(
        std::vector<std::string>{testing::bin("mtg"), "vlm", "ask", "--agent", "openai:gpt-4o", "--repeat", "12",
                                 "--parallel", "4", "--bus", bus::kDefaultUrl, "--rpm", "8", "--rate-window", "2",
                                 "--no-cache"},
        (fx_.root() / (name + ".log")).string());
  };
  auto a = asker("a");
  auto b = asker("b");
  EXPECT_EQ(a->wait(60000), 0) << testing::read_text(fx_.root() / "a.log");
  EXPECT_EQ(b->wait(60000), 0) << testing::read_text(fx_.root() / "b.log");
  const auto seen = server_.requests();
  ASSERT_EQ(seen.size(), 24u);
  EXPECT_EQ(server_.answered_429(), 0) << "the governor let too many through";
  // Any 2 s window holds at most 8 calls (a little slack for the server's own clock).
  for (std::size_t i = 0; i < seen.size(); ++i) {
    int in_window = 0;
    for (const auto& s : seen) in_window += s.at_ms >= seen[i].at_ms && s.at_ms < seen[i].at_ms + 1950.0;
    EXPECT_LE(in_window, 8) << "window starting at " << seen[i].at_ms << " ms";
  }
  EXPECT_GE(seen.back().at_ms - seen.front().at_ms, 4000.0 - 100.0) << "24 calls at 8 per 2 s need at least 4 s";
}

// The estimate before spending counts the tokens a real run sends: each request the server saw,
// counted the way the estimate counts (text at 4 characters a token, each image by its
// provider's rule; the server's own usage figure is the body's bytes / 4, base64 images
// included, which no provider bills), against the estimate of a model that solves every task,
// which the server's oracle model is. `mtg run --estimate` prints it and writes nothing.
TEST_F(VlmRunTest, TheEstimateBeforeSpendingIsWithinAQuarterOfWhatARunSends) {
  const std::vector<std::string> agents = {"openai:gpt-4o", "anthropic:claude-3-5-haiku-20241022",
                                           "gemini:gemini-2.0-flash"};
  ASSERT_EQ(mtg_run("estimated", agents, {"--estimate"}), 0) << testing::read_text(fx_.root() / "estimated.log");
  const std::string printed = testing::read_text(fx_.root() / "estimated.log");
  EXPECT_THAT(printed, HasSubstr("cost before spending: 9 episode(s) of 3 model agent(s)"));
  EXPECT_THAT(printed, HasSubstr("never ends (high)"));
  EXPECT_FALSE(fs::exists(fx_.root() / "estimated")) << "--estimate writes no run folder";
  EXPECT_TRUE(server_.requests().empty()) << "--estimate calls no model";

  ASSERT_EQ(mtg_run("run", agents, {}), 0) << testing::read_text(fx_.root() / "run.log");
  EXPECT_THAT(testing::read_text(fx_.root() / "run.log"), HasSubstr("cost before spending")) << "a run prints it before it starts";
  const orchestrator::RunPlan plan = orchestrator::load_plan(fx_.root() / "run");
  std::map<std::string, tasks::Task> by_id;
  for (auto& t : tasks::read_tasks(db_)) by_id.emplace(t.id, t);
  const nlohmann::json estimate = orchestrator::estimate_plan(plan, by_id, vlm::VlmOptions{});
  ASSERT_FALSE(estimate.is_null());
  EXPECT_EQ(estimate["stand_ins"], 0);
  EXPECT_EQ(estimate["not_estimated"], 0);

  std::map<std::string, std::int64_t> sent;  // provider -> tokens, counted as the estimate counts
  std::map<std::string, std::int64_t> calls;
  for (const auto& r : server_.requests()) {
    if (r.status != 200) continue;
    std::int64_t chars = static_cast<std::int64_t>(r.chat.system.size());
    for (const auto& [role, text] : r.chat.turns) chars += static_cast<std::int64_t>(text.size());
    const vlm::Provider provider = r.chat.provider == "anthropic" ? vlm::Provider::kAnthropic
                                   : r.chat.provider == "gemini"  ? vlm::Provider::kGemini
                                                                  : vlm::Provider::kOpenAi;
    sent[r.chat.provider] += vlm::text_tokens(chars) + static_cast<std::int64_t>(r.chat.images) *
                                                           vlm::image_tokens(provider, "low", plan.image_width,
                                                                             plan.image_height);
    ++calls[r.chat.provider];
  }
  ASSERT_EQ(sent.size(), 3u);
  for (const auto& [agent, a] : estimate["agents"].items()) {
    const std::string provider = vlm::parse_model_spec(agent).provider_name();
    const auto estimated = a["low"]["input_tokens"].get<std::int64_t>();
    const double seen = static_cast<double>(sent.at(provider));
    EXPECT_NEAR(static_cast<double>(estimated), seen, 0.25 * seen) << agent << ": estimated " << estimated << " tokens";
    EXPECT_EQ(a["low"]["calls"].get<std::int64_t>(), calls.at(provider)) << agent << ": one call per oracle key";
    EXPECT_GE(a["high"]["input_tokens"].get<std::int64_t>(), estimated);
  }
}

// --max-cost stops starting episodes once what was spent and what is in flight reaches it: the
// run exits 3 saying so, the episodes not started have no row, and the same command with a
// higher cap runs them.
TEST_F(VlmRunTest, MaxCostStopsStartingEpisodesAndAHigherCapFinishesTheRun) {
  const std::vector<std::string> agents = {"openai:gpt-4o"};
  // One at a time: the first episode's expected (or, without an estimate, its real) cost is
  // above so small a cap, so exactly one runs.
  ASSERT_EQ(mtg_run("capped", agents, {"--max-cost", "0.000001"}, 3, 1), 3) << testing::read_text(fx_.root() / "capped.log");
  const std::string log = testing::read_text(fx_.root() / "capped.log");
  EXPECT_THAT(log, HasSubstr("in flight reached --max-cost $0.0000; 2 episode(s) not started; run the same command "
                             "again with a higher --max-cost to go on"));
  auto rows = orchestrator::read_results(fx_.root() / "capped" / "results.sqlite");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_GT(rows[0].usage.spent_usd, 0.0);

  ASSERT_EQ(mtg_run("capped", agents, {"--max-cost", "1000"}, 3, 1), 0) << testing::read_text(fx_.root() / "capped.log");
  rows = orchestrator::read_results(fx_.root() / "capped" / "results.sqlite");
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& r : rows) EXPECT_TRUE(r.success) << r.task_id << ": " << r.detail;
}

}  // namespace
}  // namespace mtg
