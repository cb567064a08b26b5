// The cost estimate before spending (docs/vlm.md, "Cost before spending"): each provider's image
// rule, the conversation's growth with the history settings (checked against what Conversation
// really sends), a whole estimate on a fixed input figured by hand, and the oracle walk on a
// fixture scene.

#include "agents/vlm/cost_estimate.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "agents/vlm/conversation.h"
#include "agents/vlm/prompt_walk.h"
#include "core/tasks/generator.h"
#include "tests/support/graph_fixtures.h"

namespace mtg::vlm {
namespace {

using ::testing::HasSubstr;

TEST(CostEstimateTest, EachProviderCountsAnImageByItsOwnRule) {
  // OpenAI: 85 at low detail whatever the size; high: 85 + 170 per 512-px tile.
  EXPECT_EQ(image_tokens(Provider::kOpenAi, "low", 4096, 4096), 85);
  EXPECT_EQ(image_tokens(Provider::kOpenAi, "high", 640, 480), 85 + 170 * 2);    // 2 x 1 tiles
  EXPECT_EQ(image_tokens(Provider::kOpenAi, "high", 1024, 1024), 765);           // to 768 x 768: 2 x 2
  EXPECT_EQ(image_tokens(Provider::kOpenAi, "high", 2048, 4096), 1105);          // 1024 x 2048, then 768 x 1536: 2 x 3
  EXPECT_EQ(image_tokens(Provider::kOpenAi, "auto", 640, 480), 425) << "auto counts as high";
  EXPECT_EQ(image_tokens(Provider::kOpenAiCompatible, "low", 640, 480), 85);
  // Anthropic: width x height / 750, rounded up, the longer side at most 1568.
  EXPECT_EQ(image_tokens(Provider::kAnthropic, "low", 640, 480), 410);           // 409.6
  EXPECT_EQ(image_tokens(Provider::kAnthropic, "low", 320, 240), 103);           // 102.4
  EXPECT_EQ(image_tokens(Provider::kAnthropic, "low", 1092, 1092), 1590);        // Anthropic's own example
  EXPECT_EQ(image_tokens(Provider::kAnthropic, "low", 2000, 1000), 1640);        // 1568 x 784
  // Gemini: 258 up to 384 x 384, else 258 per 768-px tile.
  EXPECT_EQ(image_tokens(Provider::kGemini, "low", 384, 384), 258);
  EXPECT_EQ(image_tokens(Provider::kGemini, "low", 640, 480), 258);
  EXPECT_EQ(image_tokens(Provider::kGemini, "low", 2000, 1000), 258 * 6);        // 3 x 2 tiles
  // image_max_side shrinks what is sent, as images_to_send does.
  EXPECT_EQ(sent_image_size(640, 480, 0), std::make_pair(640, 480));
  EXPECT_EQ(sent_image_size(640, 480, 320), std::make_pair(320, 240));
  EXPECT_EQ(sent_image_size(640, 480, 1000), std::make_pair(640, 480));
}

const std::vector<StepPrompt> kSteps = {{200, 4, 2}, {100, 8, 1}, {100, 4, 1}};

TEST(CostEstimateTest, TheInputGrowsWithTheHistoryItKeeps) {
  // The whole episode, images on the newest step only (the defaults).
  auto calls = call_sizes(400, kSteps, 0, 1);
  ASSERT_EQ(calls.size(), 3u);
  EXPECT_EQ(calls[0].chars, 400 + 200);
  EXPECT_EQ(calls[1].chars, 400 + 200 + 4 + 100);
  EXPECT_EQ(calls[2].chars, 400 + 200 + 4 + 100 + 8 + 100);
  EXPECT_EQ(calls[0].images, 2);
  EXPECT_EQ(calls[1].images, 1);
  EXPECT_EQ(calls[2].images, 1);
  // One earlier step kept, images on the newest two.
  calls = call_sizes(400, kSteps, 1, 2);
  EXPECT_EQ(calls[1].chars, 400 + 200 + 4 + 100);
  EXPECT_EQ(calls[2].chars, 400 + 100 + 8 + 100);
  EXPECT_EQ(calls[1].images, 2 + 1);
  EXPECT_EQ(calls[2].images, 1 + 1);
  // No images kept at all.
  EXPECT_EQ(call_sizes(400, kSteps, 0, 0)[0].images, 0);
  // A model that never finishes: the steps after the first, averaged, up to the step limit.
  const auto never = never_ending_steps({400, kSteps, 5});
  ASSERT_EQ(never.size(), 5u);
  EXPECT_EQ(never[3].user_chars, 100);
  EXPECT_EQ(never[3].reply_chars, 6);
  EXPECT_EQ(never[4].images, 1);
}

TEST(CostEstimateTest, AnEstimateOnAFixedInputGivesTheFiguresWorkedOutByHand) {
  EstimateInput in;
  in.prices = PriceTable::builtin();  // gpt-4o $2.50 / $10.00, claude-3-5-haiku $0.80 / $4.00
  in.settings.rpm = 2;                 // 2 calls a minute
  in.image_width = 640;
  in.image_height = 480;
  in.prompt_version = "v3+test";
  const EpisodePrompts episode{400, kSteps, 5};
  in.episodes = {{"openai:gpt-4o", episode}, {"anthropic:claude-3-5-haiku-20241022", episode}};
  const nlohmann::json e = estimate_run(in);
  EXPECT_EQ(e["episodes"], 2);

  // Solving it: 3 calls of 600, 704 and 812 characters: 150 + 176 + 203 = 529 tokens of text,
  // 4 images; 256 tokens out at most per call.
  const nlohmann::json& openai = e["agents"]["openai:gpt-4o"];
  EXPECT_EQ(openai["image_tokens"], 85);
  EXPECT_EQ(openai["low"]["calls"], 3);
  EXPECT_EQ(openai["low"]["images"], 4);
  EXPECT_EQ(openai["low"]["input_tokens"], 529 + 4 * 85);
  EXPECT_EQ(openai["low"]["output_tokens"], 3 * 256);
  EXPECT_NEAR(openai["low"]["cost_usd"].get<double>(), (869 * 2.50 + 768 * 10.0) / 1e6, 1e-12);
  EXPECT_NEAR(openai["low"]["hours"].get<double>(), 1.5 * 60 / 3600, 1e-12);
  // Never finishing: two more calls of 916 and 1022 characters (229 + 255 tokens), one image each.
  EXPECT_EQ(openai["high"]["calls"], 5);
  EXPECT_EQ(openai["high"]["images"], 6);
  EXPECT_EQ(openai["high"]["input_tokens"], 529 + 229 + 255 + 6 * 85);
  EXPECT_EQ(openai["high"]["output_tokens"], 5 * 256);
  EXPECT_NEAR(openai["high"]["cost_usd"].get<double>(), (1523 * 2.50 + 1280 * 10.0) / 1e6, 1e-12);
  // Expected: halfway.
  EXPECT_EQ(openai["expected"]["calls"], 4);
  EXPECT_EQ(openai["expected"]["input_tokens"], (869 + 1523) / 2);
  EXPECT_NEAR(openai["expected_episode_cost_usd"].get<double>(), (0.0098525 + 0.0166075) / 2, 1e-12);

  // The same questions at Anthropic's image rule and price.
  const nlohmann::json& anthropic = e["agents"]["anthropic:claude-3-5-haiku-20241022"];
  EXPECT_EQ(anthropic["image_tokens"], 410);
  EXPECT_EQ(anthropic["low"]["input_tokens"], 529 + 4 * 410);
  EXPECT_NEAR(anthropic["low"]["cost_usd"].get<double>(), (2169 * 0.80 + 768 * 4.0) / 1e6, 1e-12);
  EXPECT_EQ(anthropic["high"]["input_tokens"], 1013 + 6 * 410);

  EXPECT_EQ(e["total"]["low"]["input_tokens"], 869 + 2169);
  EXPECT_EQ(e["total"]["low"]["calls"], 6);
  EXPECT_NEAR(e["total"]["high"]["hours"].get<double>(), 2.5 * 60 / 3600, 1e-12)
      << "each agent in its own bucket: the run takes as long as the slowest";

  const std::string text = estimate_text(e);
  EXPECT_THAT(text, HasSubstr("2 episode(s) of 2 model agent(s)"));
  EXPECT_THAT(text, HasSubstr("openai:gpt-4o: 1 episode(s), $2.50 in / $10.00 out per million tokens; 85 tokens per image"));
  EXPECT_THAT(text, HasSubstr("never ends (high)"));
  EXPECT_THAT(text, HasSubstr("all agents"));
  EXPECT_THAT(text, HasSubstr("approximated:"));

  // Without a rate limit there is no figure of hours; a model the table lacks costs nothing.
  in.settings.rpm = 0;
  in.episodes = {{"openai-compatible:http://127.0.0.1:9/v1:llava", episode}};
  in.prices = PriceTable::from_json_text(R"({"models": {}})", "test");
  const nlohmann::json bare = estimate_run(in);
  EXPECT_TRUE(bare["total"]["expected"]["hours"].is_null());
  EXPECT_FALSE(bare["agents"].begin().value()["price_known"].get<bool>());
  EXPECT_EQ(bare["total"]["expected"]["cost_usd"].get<double>(), 0.0);
  EXPECT_THAT(estimate_text(bare), HasSubstr("no rate limit set"));
}

struct WalkFixture {
  testing::FixtureDataset fx;
  testing::BuiltScene built = testing::two_tables(fx);
  tasks::Task task;

  WalkFixture() {
    tasks::TaskOptions options;
    options.levels = {1, 2};  // the fixture's three look-alike boxes make every atomic task Level 2
    const auto generated = tasks::generate_tasks(built.scene, built.graph, options);
    task = generated.set.tasks.at(0);
  }
  // The task's oracle walk with 320x240 images (or none).
  WalkedEpisode walk(bool render = true) const {
    WalkOptions w;
    w.image_width = 320;
    w.image_height = 240;
    w.render = render;
    return walk_oracle(built.graph, task, w);
  }
};

TEST(CostEstimateTest, TheOracleWalkAsksWhatTheSceneGraphServiceWouldShow) {
  WalkFixture f;
  const WalkedEpisode walked = f.walk();
  ASSERT_EQ(walked.observations.size(), f.task.oracle.size()) << "one question per key, the final 0 included";
  EXPECT_EQ(walked.replies, f.task.oracle);
  const mtg::observation_t& first = walked.observations.front();
  EXPECT_EQ(first.task_text, f.task.text);
  EXPECT_EQ(first.step, 0);
  bool overview = false;
  for (const auto& img : first.images) overview = overview || img.role == "topdown_marked";
  EXPECT_TRUE(overview) << "the first observation shows the apartment from above";
  bool platform_view = false;
  for (const auto& obs : walked.observations) {
    for (const auto& img : obs.images) platform_view = platform_view || img.role == "view_marked";
  }
  EXPECT_TRUE(platform_view);
  const WalkedEpisode text_only = f.walk(false);
  EXPECT_EQ(text_only.observations.size(), walked.observations.size());
  for (const auto& obs : text_only.observations) EXPECT_TRUE(obs.images.empty());
}

// The estimate's arithmetic of the history is what Conversation really sends, call by call.
TEST(CostEstimateTest, TheCountedCallsAreTheMessagesTheConversationSends) {
  WalkFixture f;
  const WalkedEpisode walked = f.walk();
  const PromptSet prompts = PromptSet::builtin();
  for (const auto& [history_steps, history_images] : {std::pair{0, 1}, std::pair{1, 2}, std::pair{2, 0}}) {
    VlmSettings s;
    s.history_steps = history_steps;
    s.history_images = history_images;
    const EpisodePrompts p = episode_prompts(walked, prompts, s);
    const std::vector<CallSize> counted = call_sizes(p.system_chars, p.solved, s.history_steps, s.history_images);
    mtg::episode_start_t start{};
    start.step_limit = walked.step_limit;
    Conversation c(prompts, s, start);
    ASSERT_EQ(counted.size(), walked.observations.size());
    for (std::size_t k = 0; k < walked.observations.size(); ++k) {
      const std::vector<ChatMessage> sent = c.ask(walked.observations[k]);
      std::int64_t chars = 0;
      int images = 0;
      for (const ChatMessage& m : sent) {
        chars += static_cast<std::int64_t>(m.text.size());
        images += static_cast<int>(m.images.size());
      }
      EXPECT_EQ(counted[k].chars, chars) << "call " << k << " with history " << history_steps << "/" << history_images;
      EXPECT_EQ(counted[k].images, images) << "call " << k << " with history " << history_steps << "/" << history_images;
      c.answered(walked.replies[k]);
    }
  }
}

}  // namespace
}  // namespace mtg::vlm
