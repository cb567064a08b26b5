// The model adapter's client against a real local HTTP server (tests/support/fake_model_server):
// each provider's wire format with images, every retry path the issue names (429 with
// Retry-After, 500, 529, malformed JSON, a stalled server, a cut connection), the errors that
// stop an agent, the response cache and --cache-only, and that the key never leaks into errors.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>

#include "agents/vlm/model_client.h"
#include "agents/vlm/model_spec.h"
#include "agents/vlm/voter.h"
#include "core/tasks/generator.h"
#include "tests/support/graph_fixtures.h"
#include "agents/vlm/wire.h"
#include "core/util/error.h"
#include "tests/support/fake_model_server.h"

namespace mtg::vlm {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::Behaviour;

constexpr const char* kKey = "sk-test-NEVER-LOG-THIS-KEY-42";

class AdapterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mtg_vlm_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    settings_.max_attempts = 4;
    settings_.backoff_base_s = 0.01;
    settings_.backoff_cap_s = 0.05;
    settings_.request_timeout_s = 5.0;
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::unique_ptr<ModelClient> client(const std::string& spec, ResponseCache* cache = nullptr) {
    return std::make_unique<ModelClient>(parse_model_spec(spec, server_.url() + base_path(spec)), ApiKey(kKey),
                                         settings_, PriceTable::builtin(), cache, nullptr);
  }
  static std::string base_path(const std::string& spec) { return spec.rfind("openai", 0) == 0 ? "/v1" : ""; }

  static std::vector<ChatMessage> conversation(int images = 2, const std::string& png = "iVBORw0KGgo=") {
    ChatMessage system{ChatMessage::Role::kSystem, "You are a robot.", {}};
    ChatMessage user{ChatMessage::Role::kUser, "Task: put the cup on the table\nAction?", {}};
    for (int i = 0; i < images; ++i) user.images.push_back({"image/png", png});
    return {system, user};
  }

  testing::FakeModelServer server_;
  VlmSettings settings_;
  fs::path dir_;
};

TEST(ModelSpecTest, ParsesEveryProviderAndUrlsWithPortsPathsAndColonsInModels) {
  EXPECT_EQ(parse_model_spec("openai:gpt-4o").model, "gpt-4o");
  EXPECT_EQ(parse_model_spec("anthropic:claude-3-5-sonnet-20241022").provider, Provider::kAnthropic);
  EXPECT_EQ(parse_model_spec("gemini:gemini-2.0-flash").bucket(), "gemini:gemini-2.0-flash");
  const ModelSpec c = parse_model_spec("openai-compatible:http://127.0.0.1:11434/v1:llava:13b");
  EXPECT_EQ(c.base_url, "http://127.0.0.1:11434/v1");
  EXPECT_EQ(c.model, "llava:13b");
  EXPECT_EQ(c.spec(), "openai-compatible:http://127.0.0.1:11434/v1:llava:13b");
  const ModelSpec p = parse_model_spec("openai-compatible:https://host:8080:qwen2-vl");
  EXPECT_EQ(p.base_url, "https://host:8080");
  EXPECT_EQ(p.model, "qwen2-vl");
  EXPECT_THROW(parse_model_spec("mystery:model"), Error);
  EXPECT_THROW(parse_model_spec("openai:"), Error);
  EXPECT_THROW(parse_model_spec("openai-compatible:localhost:8080"), Error);
  EXPECT_TRUE(is_model_spec("gemini:x"));
  EXPECT_FALSE(is_model_spec("oracle"));
}

TEST_F(AdapterTest, EachProviderGetsItsOwnWireFormatWithImagesAndAuthentication) {
  struct Case {
    std::string spec, path, auth_header, auth_value;
  };
  const std::vector<Case> cases = {
      {"openai:gpt-4o", "/v1/chat/completions", "authorization", std::string("Bearer ") + kKey},
      {"anthropic:claude-3-5-sonnet-20241022", "/v1/messages", "x-api-key", kKey},
      {"gemini:gemini-2.0-flash", "/v1beta/models/gemini-2.0-flash:generateContent", "x-goog-api-key", kKey}};
  server_.set_model([](const testing::SeenChat& chat) { return "Action: l" + std::to_string(chat.images); });
  for (const Case& c : cases) {
    const auto before = server_.requests().size();
    const CallResult r = client(c.spec)->call(conversation(2));
    ASSERT_TRUE(r.ok) << c.spec << ": " << r.error;
    EXPECT_EQ(r.text, "Action: l2") << c.spec;
    EXPECT_GT(r.input_tokens, 0);
    EXPECT_GT(r.output_tokens, 0);
    EXPECT_EQ(r.images, 2);
    const testing::SeenRequest seen = server_.requests().at(before);
    EXPECT_EQ(seen.path, c.path);
    EXPECT_EQ(seen.headers.at(c.auth_header), c.auth_value);
    EXPECT_EQ(seen.chat.system, "You are a robot.");
    EXPECT_EQ(seen.chat.last_turn_images, 2);
    EXPECT_EQ(seen.body.find(kKey), std::string::npos) << "the key belongs in a header, not the body";
    if (c.spec.rfind("anthropic", 0) == 0) {
      EXPECT_EQ(seen.headers.at("anthropic-version"), "2023-06-01");
    }
  }
  // The OpenAI form: a data-URI image_url with the detail level.
  const std::vector<testing::SeenRequest> seen = server_.requests();
  const auto body = nlohmann::json::parse(seen.at(0).body);
  const auto& part = body["messages"][1]["content"][1];
  EXPECT_EQ(part["type"], "image_url");
  EXPECT_EQ(part["image_url"]["url"], "data:image/png;base64,iVBORw0KGgo=");
  EXPECT_EQ(part["image_url"]["detail"], "low");
  // Gemini: inline_data; Anthropic: base64 image blocks.
  EXPECT_THAT(seen.at(1).body, HasSubstr(R"("source":{"data":"iVBORw0KGgo=","media_type":"image/png","type":"base64"})"));
  EXPECT_THAT(seen.at(2).body, HasSubstr(R"("inline_data":{"data":"iVBORw0KGgo=","mime_type":"image/png"})"));
}

TEST_F(AdapterTest, TransientFailuresAreRetriedUntilAnAnswerArrives) {
  settings_.request_timeout_s = 0.5;  // the stalled answer comes after 2 s
  server_.script({
      {Behaviour::Kind::kStatus, 429, R"({"error":{"message":"slow down","type":"rate_limit_error"}})",
       {{"retry-after-ms", "300"}}, 0, ""},
      {Behaviour::Kind::kStatus, 500, R"({"error":{"message":"internal"}})", {}, 0, ""},
      {Behaviour::Kind::kMalformed, 200, "", {}, 0, ""},
  });
  const auto started = std::chrono::steady_clock::now();
  const CallResult r = client("openai:gpt-4o")->call(conversation());
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.http_attempts, 4);
  EXPECT_GE(ms, 300.0) << "Retry-After (ms) was not honoured";

  server_.script({{Behaviour::Kind::kStall, 200, "", {}, 2000, ""},
                  {Behaviour::Kind::kCut, 200, "", {}, 0, ""},
                  {Behaviour::Kind::kStatus, 529, R"({"type":"error","error":{"type":"overloaded_error","message":"Overloaded"}})", {}, 0, ""}});
  const CallResult r2 = client("anthropic:claude-3-5-haiku-20241022")->call(conversation());
  ASSERT_TRUE(r2.ok) << r2.error;
  EXPECT_EQ(r2.http_attempts, 4) << "stall (time-out), cut connection and 529 must each be retried";
}

TEST_F(AdapterTest, RetryAfterInSecondsIsHonoured) {
  server_.script({{Behaviour::Kind::kStatus, 429, R"({"error":{"message":"rate limited","status":"RESOURCE_EXHAUSTED"}})",
                   {{"retry-after", "1"}}, 0, ""}});
  const auto started = std::chrono::steady_clock::now();
  const CallResult r = client("gemini:gemini-2.0-flash")->call(conversation());
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_GE(std::chrono::steady_clock::now() - started, std::chrono::seconds(1));
}

TEST_F(AdapterTest, ACallGivesUpAfterMaxAttemptsWithTheLastError) {
  std::vector<Behaviour> failures(4, Behaviour{Behaviour::Kind::kStatus, 503, R"({"error":{"message":"unavailable"}})", {}, 0, ""});
  server_.script(failures);
  auto c = client("openai:gpt-4o");
  const CallResult r = c->call(conversation());
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.stop_agent);
  EXPECT_THAT(r.error, HasSubstr("HTTP 503"));
  EXPECT_THAT(r.error, HasSubstr("after 4 attempts"));
  EXPECT_TRUE(c->call(conversation()).ok) << "a failed call does not stop the agent";
}

TEST_F(AdapterTest, AuthQuotaAndBillingErrorsStopTheAgentWithoutRetrying) {
  const std::vector<std::pair<Behaviour, std::string>> cases = {
      {{Behaviour::Kind::kStatus, 401, std::string(R"({"error":{"message":"Incorrect API key provided: )") + kKey + R"("}})", {}, 0, ""},
       "authentication failed"},
      {{Behaviour::Kind::kStatus, 429, R"({"error":{"message":"You exceeded your current quota","code":"insufficient_quota"}})", {}, 0, ""},
       "quota or billing"},
      {{Behaviour::Kind::kStatus, 400, R"({"type":"error","error":{"type":"invalid_request_error","message":"Your credit balance is too low"}})", {}, 0, ""},
       "quota or billing"},
      {{Behaviour::Kind::kStatus, 404, R"({"error":{"message":"model not found"}})", {}, 0, ""}, "not found"}};
  for (const auto& [behaviour, expected] : cases) {
    server_.script({behaviour});
    auto c = client("openai:gpt-4o");
    const auto before = server_.requests().size();
    const CallResult r = c->call(conversation());
    EXPECT_FALSE(r.ok);
    EXPECT_TRUE(r.stop_agent) << expected;
    EXPECT_THAT(r.error, HasSubstr(expected));
    EXPECT_EQ(r.error.find(kKey), std::string::npos) << "the key leaked into: " << r.error;
    EXPECT_EQ(server_.requests().size(), before + 1) << expected << " must not be retried";
    const CallResult again = c->call(conversation());
    EXPECT_TRUE(again.stop_agent);
    EXPECT_EQ(server_.requests().size(), before + 1) << "a stopped agent calls no more";
  }
  // A bad request fails only that call.
  server_.script({{Behaviour::Kind::kStatus, 400, R"({"error":{"message":"context too long"}})", {}, 0, ""}});
  const CallResult bad = client("openai:gpt-4o")->call(conversation());
  EXPECT_FALSE(bad.ok);
  EXPECT_FALSE(bad.stop_agent);
}

TEST_F(AdapterTest, TheCacheAnswersRepeatsAndKeysOnImageBytes) {
  ResponseCache cache(dir_ / "cache.sqlite");
  // Answers quote what was asked: the file is the owner's alone.
  EXPECT_EQ(std::filesystem::status(dir_ / "cache.sqlite").permissions() & std::filesystem::perms::all,
            std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
  settings_.cache_file = (dir_ / "cache.sqlite").string();
  const CallResult first = client("openai:gpt-4o", &cache)->call(conversation(1, "AAAA"));
  ASSERT_TRUE(first.ok);
  EXPECT_FALSE(first.cache_hit);
  EXPECT_EQ(server_.requests().size(), 1u);
  {
    ResponseCache reopened(dir_ / "cache.sqlite");  // another process, later
    const CallResult second = client("openai:gpt-4o", &reopened)->call(conversation(1, "AAAA"));
    ASSERT_TRUE(second.ok);
    EXPECT_TRUE(second.cache_hit);
    EXPECT_EQ(second.text, first.text);
    EXPECT_EQ(second.input_tokens, first.input_tokens);
    EXPECT_DOUBLE_EQ(second.cost_usd, first.cost_usd) << "the list price of a cached answer is the same";
    EXPECT_EQ(server_.requests().size(), 1u);
  }
  const CallResult other_image = client("openai:gpt-4o", &cache)->call(conversation(1, "AAAB"));
  EXPECT_FALSE(other_image.cache_hit);
  EXPECT_EQ(server_.requests().size(), 2u);
  const CallResult other_model = client("openai:gpt-4o-mini", &cache)->call(conversation(1, "AAAA"));
  EXPECT_FALSE(other_model.cache_hit);

  settings_.cache_only = true;
  const auto before = server_.requests().size();
  const CallResult miss = client("openai:gpt-4o", &cache)->call(conversation(1, "ZZZZ"));
  EXPECT_FALSE(miss.ok);
  EXPECT_THAT(miss.error, HasSubstr("--cache-only"));
  EXPECT_EQ(server_.requests().size(), before);
  EXPECT_TRUE(client("openai:gpt-4o", &cache)->call(conversation(1, "AAAA")).cache_hit);
}

TEST_F(AdapterTest, PricesComeFromTheTable) {
  const CallResult r = client("openai:gpt-4o")->call(conversation(0));
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.cost_usd, (2.50 * r.input_tokens + 10.0 * r.output_tokens) / 1e6, 1e-12);
  const CallResult local = client("openai-compatible:" + server_.url() + "/v1:llava")->call(conversation(0));
  ASSERT_TRUE(local.ok) << local.error;
  EXPECT_EQ(local.cost_usd, 0.0);
}

TEST_F(AdapterTest, ModelsVoteOnLevel4CandidatesAndCanVetoThem) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  tasks::TaskOptions o;
  o.levels = {4};
  const auto plain = tasks::generate_tasks(b.scene, b.graph, o);
  ASSERT_GE(plain.set.tasks.size(), 2u);
  const std::string victim_text = plain.set.tasks.front().text;
  server_.set_model([&](const testing::SeenChat& chat) {
    const std::string& q = chat.turns.back().second;
    EXPECT_THAT(q, HasSubstr("platform l1"));  // the scene description reached the voter
    return q.find("Task: " + victim_text + "\n") != std::string::npos ? "Not feasible: the box is fixed."
                                                                      : "**Feasible**";
  });
  ResponseCache cache(dir_ / "votes.sqlite");
  auto a = client("openai:gpt-4o", &cache);
  auto c = client("anthropic:claude-3-5-sonnet-20241022", &cache);
  const PromptSet prompts = PromptSet::builtin();
  VoteTally ta, tc;
  const std::vector<tasks::VoteBatch> voters = {
      [&](const std::vector<tasks::VoteRequest>& r) { return cast_votes(*a, prompts, r, 4, ta); },
      [&](const std::vector<tasks::VoteRequest>& r) { return cast_votes(*c, prompts, r, 4, tc); }};
  const auto voted = tasks::generate_tasks(b.scene, b.graph, o, {}, voters);
  EXPECT_EQ(voted.set.tasks.size() + 1, plain.set.tasks.size()) << "two 'Not feasible' outvote the rules";
  for (const auto& t : voted.set.tasks) EXPECT_NE(t.text, victim_text);
  EXPECT_EQ(ta.cast, static_cast<int>(plain.set.tasks.size()));
  EXPECT_EQ(ta.unreadable + ta.failed, 0);
  std::set<std::string> voter_names;
  for (const auto& v : voted.votes) voter_names.insert(v.voter);
  EXPECT_EQ(voter_names, (std::set<std::string>{"rules", "openai:gpt-4o", "anthropic:claude-3-5-sonnet-20241022"}));
  // The same generation again costs no call and gives the same votes.
  const auto calls = server_.requests().size();
  VoteTally again;
  const std::vector<tasks::VoteBatch> cached = {
      [&](const std::vector<tasks::VoteRequest>& r) { return cast_votes(*a, prompts, r, 4, again); }};
  (void)tasks::generate_tasks(b.scene, b.graph, o, {}, cached);
  EXPECT_EQ(server_.requests().size(), calls);
  EXPECT_EQ(again.cache_hits, again.asked);
}

}  // namespace
}  // namespace mtg::vlm
