#include "core/tasks/task.h"

#include "core/util/error.h"
#include "core/util/hash.h"

namespace mtg::tasks {

Ambiguity ambiguity_from_string(const std::string& name) {
  if (name == "name") return Ambiguity::kNameWithoutId;
  if (name == "category") return Ambiguity::kCategory;
  throw Error("unknown ambiguity rule '" + name + "' (use name or category)");
}

const char* to_string(Ambiguity a) { return a == Ambiguity::kCategory ? "category" : "name"; }

nlohmann::json TaskOptions::to_json() const {
  return {{"generator", kGeneratorVersion},
          {"levels", levels},
          {"ambiguity", tasks::to_string(ambiguity)},
          {"level3_count", level3_count},
          {"level3_chain", level3_chain},
          {"level4_max_moves", level4_max_moves},
          {"level4_templates", level4_templates},
          {"step_limit", rules.step_limit},
          {"min_region_size", rules.min_region_size},
          {"around_distance", goals.around_distance}};
}

std::string TaskOptions::config_hash() const { return to_hex(fnv1a64(to_json().dump())); }

}  // namespace mtg::tasks
