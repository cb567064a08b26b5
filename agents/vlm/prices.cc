#include "agents/vlm/prices.h"

#include <nlohmann/json.hpp>

#include "core/util/error.h"
#include "core/util/text.h"

namespace mtg::vlm {
extern const char* const kPricesJson;  // agents/vlm/prices.json, compiled in

PriceTable PriceTable::from_file(const std::string& file) {
  return from_json_text(read_text_file(file, "price table"), file);
}

PriceTable PriceTable::builtin() { return from_json_text(kPricesJson, "agents/vlm/prices.json"); }

PriceTable PriceTable::from_json_text(const std::string& text, const std::string& file) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(file + ": not valid JSON (" + std::string(e.what()) + ")");
  }
  if (!j.is_object() || !j.contains("models") || !j["models"].is_object()) {
    throw Error(file + ": expected {\"version\": ..., \"models\": {\"<provider>:<model>\": {...}}}");
  }
  PriceTable t;
  t.version_ = j.value("version", "");
  for (const auto& [name, p] : j["models"].items()) {
    if (!p.is_object() || !p.contains("input_per_mtok") || !p.contains("output_per_mtok") ||
        !p["input_per_mtok"].is_number() || !p["output_per_mtok"].is_number()) {
      throw Error(file + ": model '" + name + "' needs numbers input_per_mtok and output_per_mtok");
    }
    t.prices_[name] = {p["input_per_mtok"].get<double>(), p["output_per_mtok"].get<double>()};
  }
  return t;
}

const Price* PriceTable::find(const std::string& bucket) const {
  if (const auto it = prices_.find(bucket); it != prices_.end()) return &it->second;
  const Price* best = nullptr;
  std::size_t best_len = 0;
  for (const auto& [name, price] : prices_) {
    if (name.empty() || name.back() != '*') continue;
    const std::string prefix = name.substr(0, name.size() - 1);
    if (bucket.rfind(prefix, 0) == 0 && prefix.size() >= best_len) {
      best = &price;
      best_len = prefix.size();
    }
  }
  return best;
}

double PriceTable::cost_usd(const std::string& bucket, int input_tokens, int output_tokens) const {
  const Price* p = find(bucket);
  if (p == nullptr) return 0.0;
  return (p->input_per_mtok * input_tokens + p->output_per_mtok * output_tokens) / 1e6;
}

}  // namespace mtg::vlm
