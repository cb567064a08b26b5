#include "core/tasks/outcome_kinds.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "core/tasks/outcome_templates_embedded.h"
#include "core/util/error.h"
#include "core/util/json_file.h"

namespace mtg::tasks {

const std::vector<KindSpec>& outcome_kinds() {
  using K = OutcomeKind;
  static const std::vector<KindSpec> k = {
      {K::kGatherCategory, "gather_category", {"source", "target", "category", "categories", "count"},
       {{"source"}, {"target"}, {"category", "categories"}}, "two to max-moves items of one noun on one platform"},
      {K::kConsolidate, "consolidate", {"target", "category", "categories", "count", "sources"},
       {{"target"}, {"category", "categories"}, {"sources"}}, "two to max-moves items of one noun in the home"},
      {K::kClearPlatform, "clear_platform", {"source", "count"}, {{"source"}},
       "a platform holding one to max-moves items"},
      {K::kClearCategory, "clear_category", {"source", "category", "categories", "count"},
       {{"source"}, {"category", "categories"}}, "a platform holding items of two nouns"},
      {K::kArrangeOn, "arrange_on", {"object", "object2", "target"}, {{"object"}, {"object2"}, {"target"}},
       "two items a text can name"},
      {K::kTogether, "together", {"object", "object2"}, {{"object"}, {"object2"}}, "two nameable items on two platforms"},
      {K::kSetUp, "set_up", {"target", "category", "category2", "source", "source2"},
       {{"target"}, {"category"}, {"category2"}, {"source"}, {"source2"}}, "items of two nouns off one platform"},
      {K::kPutAway, "put_away", {"object", "furniture"}, {{"object"}, {"furniture"}},
       "furniture with two navigable layers, one of them inside"},
      {K::kSort, "sort", {"source", "target", "target2", "category", "categories", "category2", "categories2"},
       {{"source"}, {"target"}, {"target2"}, {"category", "categories"}, {"category2", "categories2"}},
       "a platform holding items of two nouns, at most max-moves in all"},
      {K::kMoveLayer, "move_layer", {"layer", "layer2", "furniture", "count"}, {{"layer"}, {"layer2"}, {"furniture"}},
       "furniture with two navigable layers"},
      {K::kPair, "pair", {"object", "object2"}, {{"object"}, {"object2"}}, "two nameable items"},
      {K::kSwap, "swap", {"object", "object2"}, {{"object"}, {"object2"}}, "two nameable items on two platforms"},
      {K::kLeaveExactly, "leave_exactly", {"source", "categories", "kept"}, {{"source"}, {"categories"}, {"kept"}},
       "two or more items of one noun on one platform"},
      {K::kBringSome, "bring_some", {"source", "target", "categories", "moved"},
       {{"source"}, {"target"}, {"categories"}, {"moved"}}, "two or more items of one noun on one platform"},
      {K::kKeepOne, "keep_one", {"source", "target", "category", "categories"},
       {{"source"}, {"target"}, {"category", "categories"}}, "three or more items of one noun on one platform"},
      {K::kSplit, "split", {"source", "target", "target2", "categories"},
       {{"source"}, {"target"}, {"target2"}, {"categories"}}, "two to max-moves items of one noun on one platform"},
      {K::kSpreadOut, "spread_out", {"source", "categories"}, {{"source"}, {"categories"}},
       "two or more items of one noun on one platform"},
      {K::kSeparate, "separate", {"object", "object2"}, {{"object"}, {"object2"}}, "two nameable items on one platform"},
      {K::kJoinKind, "join_kind", {"object", "categories", "target"}, {{"object"}, {"categories"}, {"target"}},
       "an item away from a platform holding two of its noun"},
      {K::kGroupAround, "group_around", {"source", "categories", "object"}, {{"source"}, {"categories"}, {"object"}},
       "two or more items of one noun on one platform, and a nameable item elsewhere"},
      {K::kClearAround, "clear_around", {"object"}, {{"object"}},
       "a nameable item with one to max-moves items standing next to it"},
      {K::kTwoPairs, "two_pairs", {"object", "object2", "object3", "object4"},
       {{"object"}, {"object2"}, {"object3"}, {"object4"}}, "four nameable items"},
      {K::kMoveAll, "move_all", {"source", "target", "count"}, {{"source"}, {"target"}},
       "a platform holding one to max-moves items"},
      {K::kKeepOnly, "keep_only", {"source", "categories"}, {{"source"}, {"categories"}},
       "a platform holding two or more items of one noun and a few others"},
      {K::kThinOut, "thin_out", {"source", "categories", "kept"}, {{"source"}, {"categories"}, {"kept"}},
       "two or more items of one noun on one platform"},
      {K::kLayOut, "lay_out", {"target", "category", "category2", "category3", "source", "source2", "source3"},
       {{"target"}, {"category"}, {"category2"}, {"category3"}, {"source"}, {"source2"}, {"source3"}},
       "items of three nouns"},
      {K::kPutInside, "put_inside", {"source", "categories", "furniture"}, {{"source"}, {"categories"}, {"furniture"}},
       "furniture with a navigable inside, and two or more items of one noun elsewhere"},
      {K::kBesideKind, "beside_kind", {"object", "category", "target"}, {{"object"}, {"category"}, {"target"}},
       "a nameable item and an item of another noun elsewhere"},
      {K::kAllButOne, "all_but_one", {"source", "category", "categories", "object"}, {{"source"}, {"category", "categories"}, {"object"}},
       "two or more items of one noun on one platform, one of them nameable"},
      {K::kFillEmpty, "fill_empty", {"source", "target", "moved"}, {{"source"}, {"target"}, {"moved"}},
       "an empty platform and one holding three or more items"},
      {K::kGatherTwo, "gather_two", {"source", "source2", "target", "categories"},
       {{"source"}, {"source2"}, {"target"}, {"categories"}}, "items of one noun on two platforms, at most max-moves"},
  };
  return k;
}

const KindSpec* spec_named(const std::string& name) {
  for (const KindSpec& k : outcome_kinds()) {
    if (name == k.name) return &k;
  }
  return nullptr;
}

std::set<std::string> placeholders_of(const std::string& text) {
  std::set<std::string> out;
  for (std::size_t pos = 0; (pos = text.find('{', pos)) != std::string::npos;) {
    const std::size_t end = text.find('}', pos);
    if (end == std::string::npos) break;
    out.insert(text.substr(pos + 1, end - pos - 1));
    pos = end + 1;
  }
  return out;
}

const char* to_string(OutcomeKind kind) {
  for (const KindSpec& k : outcome_kinds()) {
    if (k.kind == kind) return k.name;
  }
  return "unknown";
}

std::vector<OutcomeTemplate> load_templates(const std::string& source) {
  nlohmann::json doc;
  std::string origin = source;
  if (source == "builtin") {
    doc = nlohmann::json::parse(kOutcomeTemplatesJson);
    origin = "built-in outcome templates";
  } else {
    doc = read_json_file(source);
  }
  const JsonField root(doc, origin);
  const JsonField list = root.at("templates");
  std::vector<OutcomeTemplate> out;
  std::set<std::string> ids;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const JsonField t = list.at(i);
    OutcomeTemplate tmpl{t.at("id").as_string(), t.at("family").as_string(), OutcomeKind::kGatherCategory,
                         t.at("text").as_string()};
    if (!ids.insert(tmpl.id).second) t.at("id").fail("duplicate template id '" + tmpl.id + "'");
    const std::string kind = t.at("kind").as_string();
    const KindSpec* spec = spec_named(kind);
    if (spec == nullptr) t.at("kind").fail("template " + tmpl.id + ": unknown kind '" + kind + "'");
    tmpl.kind = spec->kind;
    const auto used = placeholders_of(tmpl.text);
    for (const auto& ph : used) {
      if (spec->allowed.count(ph) == 0) {
        t.at("text").fail("template " + tmpl.id + ": unknown placeholder {" + ph + "} for kind " + kind);
      }
    }
    for (const auto& alternatives : spec->required) {
      const bool present = std::any_of(alternatives.begin(), alternatives.end(),
                                       [&](const std::string& ph) { return used.count(ph) != 0; });
      if (!present) {
        t.at("text").fail("template " + tmpl.id + ": missing placeholder {" + *alternatives.begin() + "}");
      }
    }
    out.push_back(std::move(tmpl));
  }
  return out;
}

}  // namespace mtg::tasks
