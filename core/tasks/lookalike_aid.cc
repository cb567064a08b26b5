#include "core/tasks/lookalike_aid.h"

#include <algorithm>
#include <cctype>
#include <optional>
#include <set>

#include "core/tasks/phrasing.h"
#include "core/util/error.h"

namespace mtg::tasks {
namespace {

bool name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; }

// `word` at `pos` of `text` as a whole word (or name): "platform_1" is not in "platform_10".
bool whole_at(const std::string& text, std::size_t pos, std::size_t len) {
  return (pos == 0 || !name_char(text[pos - 1])) && (pos + len >= text.size() || !name_char(text[pos + len]));
}

// Where `phrase` stands in `text` as whole words, its first letter in either case (a sentence may
// start with it).
std::vector<std::size_t> occurrences(const std::string& text, const std::string& phrase) {
  std::vector<std::size_t> at;
  if (phrase.empty()) return at;
  std::string capital = phrase;
  capital[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(capital[0])));
  for (const std::string& form : {phrase, capital}) {
    for (std::size_t pos = text.find(form); pos != std::string::npos; pos = text.find(form, pos + 1)) {
      if (whole_at(text, pos, form.size())) at.push_back(pos);
    }
  }
  std::sort(at.begin(), at.end());
  at.erase(std::unique(at.begin(), at.end()), at.end());
  return at;
}

// The first of `platforms` the text names at or after `from` ("" when none).
std::string next_platform(const std::string& text, std::size_t from, const std::vector<std::string>& platforms) {
  std::size_t best = std::string::npos;
  std::string name;
  for (const std::string& p : platforms) {
    for (std::size_t pos = text.find(p, from); pos != std::string::npos; pos = text.find(p, pos + 1)) {
      if (!whole_at(text, pos, p.size())) continue;
      if (pos < best) {
        best = pos;
        name = p;
      }
      break;
    }
  }
  return name;
}

struct Span {
  std::size_t pos = 0;
  std::size_t len = 0;
  std::string words;
};

bool overlaps(const std::vector<Span>& spans, std::size_t pos, std::size_t len) {
  return std::any_of(spans.begin(), spans.end(),
                     [&](const Span& s) { return pos < s.pos + s.len && s.pos < pos + len; });
}

}  // namespace

std::map<std::string, int> close_up_labels(const std::vector<Identification>& identify) {
  std::map<std::string, int> labels;
  for (const Identification& id : identify) labels.emplace(id.object, static_cast<int>(labels.size()) + 1);
  return labels;
}

std::string close_up_words(const Identification& id, int label) {
  return "the " + (id.reference.noun.empty() ? std::string("object") : id.reference.noun) + " in close-up " +
         std::to_string(label);
}

std::string named_as(const Identification& id, const std::vector<Identification>& identify,
                     episode::LookalikeAid aid) {
  if (aid != episode::LookalikeAid::kImage) return id.phrase;
  return close_up_words(id, close_up_labels(identify).at(id.object));
}

std::string text_with_close_ups(const std::string& task_id, const std::string& text,
                                const std::vector<Identification>& identify) {
  const std::map<std::string, int> labels = close_up_labels(identify);
  std::vector<std::string> platforms;
  for (const Identification& id : identify) platforms.push_back(id.platform);
  std::vector<Span> spans;
  // The close-up's words in place of `id`'s at `pos`, capitalised where the text's word was.
  auto claim = [&](const Identification& id, std::size_t pos) {
    std::string words = close_up_words(id, labels.at(id.object));
    if (std::isupper(static_cast<unsigned char>(text[pos])) != 0) words[0] = 'T';
    spans.push_back({pos, id.phrase.size(), std::move(words)});
  };
  std::size_t after = 0;
  for (const Identification& id : identify) {
    std::vector<std::size_t> free;
    for (const std::size_t pos : occurrences(text, id.phrase)) {
      if (!overlaps(spans, pos, id.phrase.size())) free.push_back(pos);
    }
    if (free.empty()) {
      throw Error("task " + task_id + ": the look-alike words '" + id.phrase + "' are not in its text");
    }
    std::optional<std::size_t> chosen;
    for (const std::size_t pos : free) {
      if (next_platform(text, pos + id.phrase.size(), platforms) == id.platform) {
        chosen = pos;
        break;
      }
    }
    if (!chosen) {
      const auto later = std::find_if(free.begin(), free.end(), [&](std::size_t pos) { return pos >= after; });
      chosen = later != free.end() ? *later : free.front();
    }
    claim(id, *chosen);
    after = *chosen + id.phrase.size();
  }
  // A text may name one object twice ("put X where Y is, and Y where X is"): each further
  // occurrence goes to the one object with those words, or to the one whose platform follows.
  for (const Identification& id : identify) {
    std::set<std::string> sharing;
    for (const Identification& other : identify) {
      if (other.phrase == id.phrase) sharing.insert(other.object);
    }
    for (const std::size_t pos : occurrences(text, id.phrase)) {
      if (overlaps(spans, pos, id.phrase.size())) continue;
      if (sharing.size() > 1 && next_platform(text, pos + id.phrase.size(), platforms) != id.platform) continue;
      claim(id, pos);
    }
  }
  std::sort(spans.begin(), spans.end(), [](const Span& a, const Span& b) { return a.pos > b.pos; });
  std::string out = text;
  for (const Span& s : spans) out.replace(s.pos, s.len, s.words);
  return out;
}

TaskWords task_words(const std::string& task_id, const std::string& text, const std::vector<Identification>& identify,
                     episode::LookalikeAid aid, bool with_images) {
  TaskWords words;
  switch (aid) {
    case episode::LookalikeAid::kBoth:
      return {text, lookalike_hint(identify, with_images)};
    case episode::LookalikeAid::kWords:
      return {text, lookalike_hint(identify, false)};
    case episode::LookalikeAid::kImage:
      break;
  }
  if (!with_images) {
    throw Error("task " + task_id + ": the look-alike aid 'image' needs observations with images");
  }
  if (identify.empty()) return {text, ""};
  words.text = text_with_close_ups(task_id, text, identify);
  // Labels run in the order objects are first named: each object's first identification, in turn.
  const std::map<std::string, int> labels = close_up_labels(identify);
  std::vector<std::string> where;
  std::set<std::string> listed;
  for (const Identification& id : identify) {
    if (!listed.insert(id.object).second) continue;
    where.push_back("close-up " + std::to_string(labels.at(id.object)) + " on " + id.platform);
  }
  words.hint = "Some objects of this task have look-alikes; the task names each by the close-up image that shows it: ";
  for (std::size_t i = 0; i < where.size(); ++i) {
    if (i > 0) words.hint += i + 1 == where.size() ? " and " : ", ";
    words.hint += where[i];
  }
  words.hint += ". A close-up shows the object where it stands, seen from where you arrive at its platform, every "
                "other object faded.";
  return words;
}

}  // namespace mtg::tasks
