// The adapter's pure parts: prompts and conversation windows, the reply parser on a corpus of
// messy model replies, verdicts, delay headers, the rate window's arithmetic and settings files.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <set>

#include <filesystem>
#include <fstream>

#include "agents/vlm/conversation.h"
#include "agents/vlm/encoding.h"
#include "core/episode/model_request.h"
#include "agents/vlm/prompt.h"
#include "agents/vlm/retry_policy.h"
#include "agents/vlm/secrets.h"
#include "agents/vlm/settings.h"
#include "agents/vlm/voter.h"
#include "core/episode/reply_parser.h"
#include "core/episode/rules.h"
#include "core/tasks/feasibility.h"
#include "core/util/error.h"
#include "core/util/rate_window.h"

namespace mtg::vlm {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

mtg::observation_t observation(int step, int images) {
  mtg::observation_t o{};
  o.step = step;
  o.step_limit = 15;
  o.task_text = "Move the red cup to table_4.";
  o.text = "You are at the start position.";
  o.hint = step == 1 ? "'l9' is not an action here." : "";
  for (const char* key : {"0", "l1", "l2"}) {
    mtg::action_option_t a{};
    a.key = key;
    a.description = std::string("do ") + key;
    o.actions.push_back(a);
  }
  o.n_actions = 3;
  for (int i = 0; i < images; ++i) {
    mtg::image_t img{};
    img.role = i == 0 ? "view_marked" : (i == 1 ? "view" : "item");
    img.encoding = "png";
    img.width = 4;
    img.height = 4;
    img.data = {0x89, 'P', 'N', 'G', static_cast<std::uint8_t>(step)};
    img.nbytes = static_cast<int32_t>(img.data.size());
    o.images.push_back(img);
  }
  o.n_images = images;
  return o;
}

TEST(PromptTest, TheShippedTemplatesLoadAndCarryAVersionWithTheirHash) {
  const PromptSet p = PromptSet::builtin();
  EXPECT_THAT(p.version, ::testing::StartsWith("v3+"));
  EXPECT_EQ(p.version.size(), 11u);
  const PromptSet from_files = PromptSet::load(std::string(MTG_SOURCE_DIR) + "/agents/vlm/prompts/v3");
  EXPECT_EQ(from_files.version, p.version) << "the compiled-in templates are the shipped files";
  EXPECT_THAT(render_template("a {{ x }} b {{y}}", {{"x", "1"}, {"y", "2"}}, "t"), "a 1 b 2");
  try {
    render_template("hello {{nobody}}", {}, "prompts/step.txt");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "prompts/step.txt: unknown placeholder {{nobody}}");
  }
}

// The model is told the environment's convention (rules.h), not a paraphrase that could drift.
TEST(PromptTest, TheSystemPromptStatesTheDirectionConventionOfTheEnvironment) {
  const PromptSet p = PromptSet::builtin();
  const std::string system =
      render_template(p.system, {{"step_limit", "15"}, {"directions", episode::direction_convention()}}, "system.txt");
  EXPECT_THAT(system, ::testing::HasSubstr(episode::direction_convention()));
  EXPECT_THAT(system, ::testing::Not(::testing::HasSubstr("front is the part nearest")));  // what v1 said
}

TEST(PromptTest, AnEditedTemplateGetsANewVersion) {
  const fs::path dir = fs::temp_directory_path() / ("mtg_prompts_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const PromptSet base = PromptSet::builtin();
  auto write = [&](const char* name, const std::string& text) { std::ofstream(dir / name) << text; };
  write("VERSION", "v1\n");
  write("system.txt", base.system + " Be brief.");
  write("step.txt", base.step);
  write("vote.txt", base.vote);
  const PromptSet edited = PromptSet::load(dir.string());
  EXPECT_THAT(edited.version, ::testing::StartsWith("v1+"));
  EXPECT_NE(edited.version, base.version);
  write("step.txt", "{{task}} {{weather}}");
  EXPECT_THROW(PromptSet::load(dir.string()), Error);
  fs::remove_all(dir);
}

TEST(ConversationTest, StepsCarryTaskActionsHintAndImagesAndTheHistoryIsWindowed) {
  const PromptSet prompts = PromptSet::builtin();
  VlmSettings s;
  s.history_steps = 2;
  s.history_images = 1;
  s.image_roles = {"view_marked", "item"};
  mtg::episode_start_t start{};
  start.step_limit = 15;
  Conversation c(prompts, s, start);
  auto m0 = c.ask(observation(0, 3));
  ASSERT_EQ(m0.size(), 2u);
  EXPECT_EQ(m0[0].role, ChatMessage::Role::kSystem);
  EXPECT_THAT(m0[0].text, HasSubstr("at most 15 steps"));
  EXPECT_THAT(m0[1].text, HasSubstr("Task: Move the red cup to table_4."));
  EXPECT_THAT(m0[1].text, HasSubstr("- l2: do l2"));
  EXPECT_THAT(m0[1].text, HasSubstr("Image 2: the object in your hand."));
  EXPECT_EQ(m0[1].images.size(), 2u) << "only the configured roles are sent";
  c.answered("l9");
  auto m1 = c.ask(observation(1, 3));
  EXPECT_THAT(m1.back().text, HasSubstr("Feedback on your last action: 'l9' is not an action here."));
  c.answered("l1");
  c.ask(observation(2, 3));
  c.answered("l2");
  auto m3 = c.ask(observation(3, 3));
  // system + 2 earlier steps (user, assistant) + this question
  ASSERT_EQ(m3.size(), 6u);
  EXPECT_THAT(m3[1].text, HasSubstr("Step 2 of 15"));
  EXPECT_EQ(m3[2].text, "l1");
  EXPECT_TRUE(m3[1].images.empty()) << "older steps lose their images";
  EXPECT_EQ(m3[5].images.size(), 2u);
}

// What the adapter records of each request (agent_action_t.request) gives back, in full, every
// message it sent: texts, order, and which images with the bytes' digest, though each record
// writes only its own step's question.
TEST(ConversationTest, TheRecordOfEachRequestGivesBackExactlyWhatWasSent) {
  const PromptSet prompts = PromptSet::builtin();
  VlmSettings s;
  s.history_steps = 2;
  s.history_images = 2;
  s.image_roles = {"view_marked", "item"};
  mtg::episode_start_t start{};
  start.step_limit = 15;
  Conversation c(prompts, s, start);
  std::map<int, std::string> records, replies;
  std::map<int, std::vector<ChatMessage>> sent;
  std::map<std::pair<int, int>, std::string> digests;  // (step, image index) -> sha256 of the bytes
  for (int step = 0; step < 5; ++step) {
    const auto obs = observation(step, 3);
    for (std::size_t i = 0; i < obs.images.size(); ++i) {
      const auto& d = obs.images[i].data;
      digests[{step, static_cast<int>(i)}] = sha256_hex({reinterpret_cast<const char*>(d.data()), d.size()});
    }
    sent[step] = c.ask(obs);
    records[step] = c.last_request();
    replies[step] = "l" + std::to_string(step + 1) + " because";
    c.answered(replies[step]);
  }
  EXPECT_LT(records[4].size(), 2 * records[1].size()) << "a record does not repeat earlier turns' texts";
  const auto full = episode::resolve_requests(records, replies);
  ASSERT_EQ(full.size(), 5u);
  for (const auto& [step, messages] : sent) {
    const auto& got = full.at(step)["messages"];
    ASSERT_EQ(got.size(), messages.size()) << "step " << step;
    EXPECT_EQ(full.at(step)["params"]["history_images"], 2);
    for (std::size_t i = 0; i < messages.size(); ++i) {
      EXPECT_EQ(got[i]["text"], messages[i].text) << "step " << step << " message " << i;
      ASSERT_EQ(got[i]["images"].size(), messages[i].images.size()) << "step " << step << " message " << i;
      for (const auto& img : got[i]["images"]) {
        EXPECT_EQ(img["sha256"], digests.at({img["step"].get<int>(), img["index"].get<int>()}));
      }
    }
  }
  // A lost record (a damaged recording) is named, not invented.
  records.erase(1);
  const auto cut = episode::resolve_requests(records, replies);
  bool named = false;
  for (const auto& m : cut.at(2)["messages"]) named = named || (m.value("step", -1) == 1 && m.value("missing", false));
  EXPECT_TRUE(named);
}

// A real key that is not offered ("l7" where the platforms are l3 and l12) is read as that key:
// the rules refuse it as unavailable, with the reason; only a reply with no key is a format error.
TEST(ReplyParserCorpusTest, MessyRepliesGiveTheOfferedKeyOrAFormatError) {
  const std::vector<std::string> offered = {"0", "l3", "l12", "o1", "o2", "-1", "startplace", "999", "5"};
  const std::vector<std::pair<std::string, std::string>> corpus = {
      {"l12", "l12"},
      {"  L12.  ", "l12"},
      {"`l3`", "l3"},
      {"**o2**", "o2"},
      {"\"startplace\"", "startplace"},
      {"'-1'", "-1"},
      {"```\nl12\n```", "l12"},
      {"```text\no1\n```\nThat picks the mug.", "o1"},
      {"Action: l3", "l3"},
      {"I should go to the table first.\nAction: l12", "l12"},
      {"Thinking... the cup is on l3 but I need l12.\nFinal answer: l12", "l12"},
      {"Answer: 999 (anywhere it fits)", "999"},
      {"l12\nBecause the cup stands there.", "l12"},
      {"I will pick object 2: o2", "o2"},
      {"", ""},
      {"   \n", ""},
      {"I am not sure what to do.", ""},
      {"Either l3 or l12 would work.", ""},
      {"l7", "l7"},
      {"Action: l99", "l99"},
      {"I see 3 books on l7", "l7"},
  };
  const std::set<std::string> not_offered = {"l7", "l99"};
  for (const auto& [reply, expected] : corpus) {
    const episode::ParsedReply p = episode::parse_reply(reply, offered);
    EXPECT_EQ(p.key, expected) << "reply: " << reply;
    EXPECT_EQ(p.ok, !expected.empty()) << "reply: " << reply;
    EXPECT_EQ(p.offered, p.ok && not_offered.count(p.key) == 0) << "reply: " << reply;
    if (!p.ok) {
      EXPECT_FALSE(p.why.empty()) << "a format error names its cause";
    }
  }
}

TEST(VoterTest, VerdictsAreReadFromFreeText) {
  EXPECT_EQ(parse_verdict("Feasible"), tasks::kFeasible);
  EXPECT_EQ(parse_verdict("**Partially feasible** - the bowl is hidden."), tasks::kPartiallyFeasible);
  EXPECT_EQ(parse_verdict("Not feasible."), tasks::kNotFeasible);
  EXPECT_EQ(parse_verdict("This looks infeasible to me"), tasks::kNotFeasible);
  EXPECT_EQ(parse_verdict("maybe"), "");
  EXPECT_EQ(parse_verdict("Feasible or not feasible, hard to say"), "");
}

TEST(RetryPolicyTest, DelayHeadersInEveryProviderForm) {
  HttpResponse r;
  r.headers = {{"retry-after-ms", "1500"}};
  EXPECT_DOUBLE_EQ(header_delay_ms(r), 1500.0);
  r.headers = {{"retry-after", "7"}};
  EXPECT_DOUBLE_EQ(header_delay_ms(r), 7000.0);
  r.headers = {{"x-ratelimit-reset-requests", "6m0s"}, {"x-ratelimit-reset-tokens", "20ms"}};
  EXPECT_DOUBLE_EQ(header_delay_ms(r), 360000.0);
  r.headers = {{"retry-after", "Wed, 21 Oct 2015 07:28:00 GMT"}};
  EXPECT_DOUBLE_EQ(header_delay_ms(r), 0.0) << "a date in the past: no wait";
  r.headers = {};
  EXPECT_DOUBLE_EQ(header_delay_ms(r), -1.0);
  // Back-off without a server delay: exponential, capped, jittered deterministically.
  const Classified c{Outcome::kRetry, "", -1.0};
  const Backoff b{1.0, 8.0};
  EXPECT_DOUBLE_EQ(retry_delay_ms(c, 2, b, 42), retry_delay_ms(c, 2, b, 42));
  for (int k = 0; k < 8; ++k) {
    const double d = retry_delay_ms(c, k, b, 7);
    const double full = 1000.0 * std::min(8.0, static_cast<double>(1 << k));
    EXPECT_GE(d, full / 2);
    EXPECT_LE(d, full);
  }
}

TEST(RateWindowTest, CallsAndTokensStayWithinTheWindow) {
  RateWindow w;
  const RateLimits limits{3, 1000, std::chrono::milliseconds(1000)};
  const auto t0 = RateClock::time_point{} + std::chrono::hours(1);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(w.wait_for(limits, 100, t0), RateClock::duration::zero());
    w.admit(i, 100, t0 + std::chrono::milliseconds(100 * i));
  }
  // The fourth waits until the first leaves the window.
  EXPECT_EQ(w.wait_for(limits, 100, t0 + std::chrono::milliseconds(250)), std::chrono::milliseconds(750));
  EXPECT_EQ(w.wait_for(limits, 100, t0 + std::chrono::milliseconds(1000)), RateClock::duration::zero());
  // Tokens: 3 x 100 used; a 900-token call waits for room.
  RateWindow t;
  const RateLimits tokens{0, 1000, std::chrono::milliseconds(1000)};
  t.admit(1, 400, t0);
  t.admit(2, 400, t0 + std::chrono::milliseconds(500));
  EXPECT_EQ(t.wait_for(tokens, 300, t0 + std::chrono::milliseconds(600)), std::chrono::milliseconds(400));
  t.settle(1, 100);  // it used less than estimated
  EXPECT_EQ(t.wait_for(tokens, 300, t0 + std::chrono::milliseconds(600)), RateClock::duration::zero());
  t.pause_until(t0 + std::chrono::seconds(5));
  EXPECT_EQ(t.wait_for(tokens, 1, t0 + std::chrono::seconds(4)), std::chrono::seconds(1));
}

TEST(SettingsTest, FilesAreCheckedFieldByField) {
  const fs::path f = fs::temp_directory_path() / ("mtg_vlm_settings_" + std::to_string(::getpid()) + ".json");
  std::ofstream(f) << R"({"temperature": 0.2, "rpm": 30, "history_steps": 4})";
  const VlmSettings s = VlmSettings::from_json_file(f.string());
  EXPECT_DOUBLE_EQ(s.temperature, 0.2);
  EXPECT_EQ(s.rpm, 30);
  std::ofstream(f) << R"({"temprature": 0.2})";
  try {
    VlmSettings::from_json_file(f.string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("unknown field 'temprature'"));
  }
  std::ofstream(f) << R"({"image_detail": "ultra"})";
  EXPECT_THROW(VlmSettings::from_json_file(f.string()), Error);
  fs::remove(f);
}

TEST(SecretsTest, KeysComeFromAFileOrTheEnvironmentAndAreRedacted) {
  const fs::path f = fs::temp_directory_path() / ("mtg_keys_" + std::to_string(::getpid()));
  std::ofstream(f) << "# keys\nexport ANTHROPIC_API_KEY=sk-ant-123456\nOPENAI_API_KEY = sk-oa-abcdef\n";
  EXPECT_EQ(load_api_key(parse_model_spec("openai:gpt-4o"), f.string()).reveal(), "sk-oa-abcdef");
  EXPECT_EQ(load_api_key(parse_model_spec("anthropic:x"), f.string()).reveal(), "sk-ant-123456");
  try {
    load_api_key(parse_model_spec("gemini:x"), f.string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("GEMINI_API_KEY"));
    EXPECT_EQ(std::string(e.what()).find("sk-"), std::string::npos);
  }
  const ApiKey key("sk-oa-abcdef");
  EXPECT_EQ(key.redact("bad key sk-oa-abcdef (sk-oa-abcdef)"), "bad key [redacted] ([redacted])");
  ::unsetenv("OPENAI_COMPATIBLE_API_KEY");
  EXPECT_TRUE(load_api_key(parse_model_spec("openai-compatible:http://h:1:m"), "").empty());
  fs::remove(f);
}

}  // namespace
}  // namespace mtg::vlm
