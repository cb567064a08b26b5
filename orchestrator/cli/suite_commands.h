#pragma once
// `mtg suite make | info | verify` (docs/suites.md).

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace mtg::cli {

struct SuiteMakeOptions {
  std::string tasks;                // task database to draw from
  std::vector<std::string> scenes;  // empty = every scene of the set
  std::string levels = "1,2,3,4";
  int per_level = 0;                // tasks per (scene, level); or chosen from power with --mde
  double mde = 0.0;                 // SR points a paired comparison should detect (0 = not given)
  double power = 0.8;
  double discordance = 0.3;         // share of tasks where exactly one of two agents succeeds
  double alpha = 0.05;
  std::uint64_t seed = 0;
  std::string draw = "stratified";
  std::string name;
  std::string out;
  std::set<std::string> given;      // options given on the command line
};

struct SuiteInfoOptions {
  std::string file;
  bool json = false;
};

struct SuiteVerifyOptions {
  std::string file;
  std::string data_dir;
  std::string profile = "replica_cad";
};

int run_suite_make(const SuiteMakeOptions& options);
int run_suite_info(const SuiteInfoOptions& options);
int run_suite_verify(const SuiteVerifyOptions& options);

/// The tasks per (scene, level) a paired comparison needs (McNemar, core/stats/power.h), over
/// `scenes` scenes, and the lines that say how it was found. @throws mtg::Error on inputs out of range.
struct SuiteSizing {
  int per_scene = 0;
  std::int64_t per_level = 0;
  std::vector<std::string> explanation;
};
SuiteSizing size_suite(double mde_points, double power, double discordance, double alpha, int scenes);

}  // namespace mtg::cli
