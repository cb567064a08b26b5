#include "agents/vlm/prompt.h"

#include <filesystem>
#include <vector>

#include "core/util/error.h"
#include "core/util/hash.h"
#include "core/util/text.h"

namespace mtg::vlm {
// Compiled in from agents/vlm/prompts/v3 (agents/CMakeLists.txt).
extern const char* const kPromptV3Version;
extern const char* const kPromptV3System;
extern const char* const kPromptV3Step;
extern const char* const kPromptV3Vote;
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& file) { return read_text_file(file, "prompt template"); }

// Renders with every allowed placeholder set, so an unknown one fails now.
void check(const std::string& text, const std::vector<std::string>& allowed, const fs::path& file) {
  std::map<std::string, std::string> vars;
  for (const auto& name : allowed) vars[name] = "";
  render_template(text, vars, file.string());
}

}  // namespace

std::string render_template(std::string_view text, const std::map<std::string, std::string>& vars,
                            const std::string& origin) {
  std::string out;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const auto open = text.find("{{", pos);
    if (open == std::string_view::npos) break;
    const auto close = text.find("}}", open + 2);
    if (close == std::string_view::npos) throw Error(origin + ": unclosed '{{'");
    const std::string name = trim_whitespace(text.substr(open + 2, close - open - 2));
    const auto it = vars.find(name);
    if (it == vars.end()) throw Error(origin + ": unknown placeholder {{" + name + "}}");
    out.append(text.substr(pos, open - pos));
    out += it->second;
    pos = close + 2;
  }
  out.append(text.substr(pos));
  return out;
}

namespace {

PromptSet checked(PromptSet p, const std::string& version) {
  const fs::path d(p.dir);
  if (version.empty()) throw Error((d / "VERSION").string() + ": empty prompt version");
  check(p.system, {"step_limit", "directions"}, d / "system.txt");
  check(p.step, {"task", "step", "steps_used", "step_limit", "situation", "hint", "actions", "images"}, d / "step.txt");
  check(p.vote, {"task", "scene", "step_limit"}, d / "vote.txt");
  const std::uint64_t h = fnv1a64(p.vote, fnv1a64(p.step, fnv1a64(p.system)));
  p.version = version + "+" + to_hex(h).substr(0, 8);
  return p;
}

}  // namespace

PromptSet PromptSet::load(const std::string& dir) {
  const fs::path d(dir);
  PromptSet p;
  p.dir = dir;
  p.system = read_text(d / "system.txt");
  p.step = read_text(d / "step.txt");
  p.vote = read_text(d / "vote.txt");
  return checked(std::move(p), trim_whitespace(read_text(d / "VERSION")));
}

PromptSet PromptSet::builtin() {
  PromptSet p;
  p.dir = "agents/vlm/prompts/v3";
  p.system = kPromptV3System;
  p.step = kPromptV3Step;
  p.vote = kPromptV3Vote;
  return checked(std::move(p), trim_whitespace(kPromptV3Version));
}

}  // namespace mtg::vlm
