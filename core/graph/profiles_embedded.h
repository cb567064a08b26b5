#pragma once
// Built-in scene profiles, embedded from core/graph/profiles/*.json at build time.

namespace mtg::graph {
extern const char* const kReplicaCadProfileJson;
}
