#pragma once
// The provider-neutral conversation an adapter sends: messages with text and images, and the
// generation parameters. wire.h turns it into each provider's request body.

#include <optional>
#include <string>
#include <vector>

namespace mtg::vlm {

struct ImagePart {
  std::string mime;     // "image/png" or "image/jpeg"
  std::string base64;   // the encoded file, base64 (encoded once, resent with the history)
};

struct ChatMessage {
  enum class Role { kSystem, kUser, kAssistant };
  Role role = Role::kUser;
  std::string text;
  std::vector<ImagePart> images;  // user messages only
};

struct GenerationParams {
  double temperature = 0.0;
  int max_output_tokens = 256;
  std::string image_detail = "low";
  std::optional<int> seed;
};

/// What a model answered, and what it cost in tokens.
struct ModelAnswer {
  std::string text;
  int input_tokens = 0;
  int output_tokens = 0;
};

}  // namespace mtg::vlm
