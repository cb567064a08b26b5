#pragma once
// The coordinator's run announcement (run_info_t) and the runtime configuration a worker builds
// from it: the two directions of one mapping, kept side by side so a new setting travels both ways.

#include "mtg/run_info_t.hpp"
#include "orchestrator/run/launcher.h"
#include "orchestrator/run/local_runtime.h"

namespace mtg::orchestrator::remote {

/// What workers need to start `run`'s processes, and the progress so far (`header` unset).
mtg::run_info_t announcement(const RuntimeConfig& run, const RunCounts& counts);

/// The settings announced for the run; bus, parallelism and host-local options are the worker's.
RuntimeConfig announced_config(const mtg::run_info_t& info);

}  // namespace mtg::orchestrator::remote
