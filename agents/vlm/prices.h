#pragma once
// The price table (agents/vlm/prices.json): US dollars per million input and output tokens per
// "<provider>:<model>", with '*' at the end of a name matching any model that starts so. Image
// inputs are billed as input tokens by every provider, so tokens are all the table needs.

#include <map>
#include <string>

namespace mtg::vlm {

struct Price {
  double input_per_mtok = 0.0;
  double output_per_mtok = 0.0;
};

class PriceTable {
 public:
  PriceTable() = default;
  /// @throws mtg::Error naming the file and entry.
  static PriceTable from_file(const std::string& file);
  /// `origin` names the text in errors.
  static PriceTable from_json_text(const std::string& text, const std::string& origin);
  /// The shipped table (agents/vlm/prices.json), compiled in.
  static PriceTable builtin();
  /// The exact entry, else the longest matching '*' entry; nullptr if none.
  const Price* find(const std::string& bucket) const;
  double cost_usd(const std::string& bucket, int input_tokens, int output_tokens) const;
  const std::string& version() const { return version_; }

 private:
  std::string version_;
  std::map<std::string, Price> prices_;
};

}  // namespace mtg::vlm
