#pragma once
// Prompt templates, versioned in files (agents/vlm/prompts/<version>/): system.txt, step.txt,
// vote.txt and VERSION. The shipped version is compiled in; --prompts DIR uses another. Placeholders are {{name}}; a template naming an unknown placeholder is an
// error when it is loaded, not in the middle of a run. The version recorded with every result is
// VERSION plus a hash of the templates, so an edited template never passes for the old one.

#include <map>
#include <string>
#include <string_view>

namespace mtg::vlm {

struct PromptSet {
  std::string dir;
  std::string version;   // e.g. "v2+3fa2c1d0"
  std::string system;    // placeholders: step_limit, directions (episode::direction_convention)
  std::string step;      // task, step, steps_used, step_limit, situation, hint, actions, images
  std::string vote;      // task, scene, step_limit

  /// @throws mtg::Error naming the file (missing, or an unknown placeholder).
  static PromptSet load(const std::string& dir);
  /// The shipped set (agents/vlm/prompts/v3), compiled in.
  static PromptSet builtin();
};

/// Replaces every {{name}} by vars[name]. @throws mtg::Error naming `origin` and the placeholder.
std::string render_template(std::string_view text, const std::map<std::string, std::string>& vars,
                            const std::string& origin);

}  // namespace mtg::vlm
