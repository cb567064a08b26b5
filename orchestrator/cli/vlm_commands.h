#pragma once
// `mtg vlm ask`: one prompt (and images) to a model agent through the same client the adapters
// use: a connection and key check, and, repeated in parallel (--repeat, --parallel) with --bus,
// a load generator that shares the run's rate governor (used by the governor test and bench).

#include <string>
#include <vector>

#include "agents/vlm/options.h"

namespace mtg::cli {

struct VlmAskOptions {
  std::string agent;                 // openai:<model>, ...
  std::string text = "Reply with the word ready.";
  std::vector<std::string> images;   // PNG or JPEG files
  int repeat = 1;
  int parallel = 1;
  std::string bus_url;               // "" = a local rate gate; else the governor on this bus
  bool json = false;                 // one JSON line per call on stdout
  vlm::VlmOptions vlm;
};

int run_vlm_ask(const VlmAskOptions& options);

}  // namespace mtg::cli
