#include "orchestrator/remote/slurm_workers.h"

#include <wordexp.h>

#include <filesystem>
#include <fstream>

#include "bus/process/subprocess.h"
#include "core/util/error.h"
#include "core/util/log.h"

namespace mtg::orchestrator::remote {
namespace {

namespace fs = std::filesystem;

// A shell word that stays one word whatever it holds.
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::vector<std::string> split_options(const std::string& options) {
  if (options.find_first_not_of(" \t") == std::string::npos) return {};
  wordexp_t words{};
  // WRDE_NOCMD: a $(...) in the options is refused, not run.
  const int rc = ::wordexp(options.c_str(), &words, WRDE_NOCMD | WRDE_SHOWERR);
  if (rc != 0) {
    if (rc != WRDE_NOSPACE) throw Error("--slurm options '" + options + "' do not parse as sbatch options (unbalanced quotes or $(...)?)");
    ::wordfree(&words);
    throw Error("--slurm options: out of memory");
  }
  std::vector<std::string> out(words.we_wordv, words.we_wordv + words.we_wordc);
  ::wordfree(&words);
  return out;
}

}  // namespace

std::string worker_job_script(const SlurmRequest& r) {
  std::string s = "#!/bin/sh\n";
  s += "# One worker of mtg run " + r.run_id + " (written by mtg run --slurm; docs/multihost.md).\n";
  s += "task=\"${SLURM_ARRAY_TASK_ID:-0}\"\n";
  s += "exec " + quoted(r.mtg_binary) + " worker --once --run " + quoted(r.run_id) + " --bus " + quoted(r.bus_url) +
       " --bus-key " + quoted(r.bus_key) + " --capacity " + std::to_string(r.capacity) +
       " --name \"slurm-${SLURM_ARRAY_JOB_ID:-0}_$task\" --dir " + quoted((fs::path(r.dir) / "worker-").string()) +
       "\"$task\"";
  if (!r.data_dir.empty()) s += " --data " + quoted(r.data_dir);
  return s + "\n";
}

std::vector<std::string> sbatch_command(const SlurmRequest& r, const std::string& script_path) {
  if (r.workers < 1) throw Error("--slurm-workers must be at least 1, not " + std::to_string(r.workers));
  std::vector<std::string> argv = {"sbatch",
                                   "--parsable",
                                   "--array=0-" + std::to_string(r.workers - 1),
                                   "--job-name=mtg-" + r.run_id,
                                   "--output=" + (fs::path(r.dir) / "worker-%a.log").string()};
  for (auto& o : split_options(r.sbatch_options)) argv.push_back(std::move(o));
  argv.push_back(script_path);
  return argv;
}

SlurmWorkers::SlurmWorkers(const SlurmRequest& r) {
  fs::create_directories(r.dir);
  const fs::path script = fs::path(r.dir) / "worker.sh";
  {
    std::ofstream out(script);
    out << worker_job_script(r);
    if (!out) throw Error("cannot write " + script.string());
  }
  fs::permissions(script, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec);
  const auto argv = sbatch_command(r, script.string());
  process::CommandOutput submitted;
  try {
    submitted = process::run_command(argv);
  } catch (const Error& e) {
    throw Error(std::string("cannot submit the workers to Slurm: ") + e.what());
  }
  std::string out = submitted.output;
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  if (submitted.exit_code == 127) throw Error("--slurm needs sbatch on the PATH (Slurm's client commands)");
  if (submitted.exit_code != 0 || out.empty()) throw Error("sbatch refused the workers: " + out);
  // --parsable prints "<job id>" or "<job id>;<cluster>", after any warnings.
  const auto newline = out.find_last_of('\n');
  const std::string last = newline == std::string::npos ? out : out.substr(newline + 1);
  job_id_ = last.substr(0, last.find(';'));
  if (job_id_.empty() || job_id_.find_first_not_of("0123456789") != std::string::npos) {
    throw Error("sbatch answered '" + out + "', not a job id");
  }
  std::ofstream(fs::path(r.dir) / "job_id") << job_id_ << '\n';
}

SlurmWorkers::~SlurmWorkers() {
  try {
    const auto cancelled = process::run_command({"scancel", job_id_});
    if (cancelled.exit_code != 0) log::warn("scancel " + job_id_ + ": " + cancelled.output);
  } catch (const std::exception& e) {
    log::warn("cannot cancel Slurm job " + job_id_ + ": " + e.what());
  }
}

}  // namespace mtg::orchestrator::remote
