#pragma once
// Workers from a Slurm cluster (`mtg run --slurm`, docs/multihost.md "Slurm"): the coordinator
// submits `mtg worker --once --run <id>` as one job array, one array task per worker, and
// cancels the array when the run ends or is interrupted. Each task is one host of the run: it
// joins over the shared bus (usually a TCP hub, since cluster networks rarely carry multicast),
// and a node that dies is a lost host as anywhere else (its leases expire and its episodes run
// elsewhere).

#include <string>
#include <vector>

namespace mtg::orchestrator::remote {

struct SlurmRequest {
  std::string sbatch_options;  // the user's, split as a shell would (no substitutions)
  int workers = 1;             // array tasks
  int capacity = 2;            // episodes at once per worker
  std::string mtg_binary;      // absolute; the nodes must see it at this path
  std::string bus_url;         // the shared bus the workers join
  std::string bus_key;         // key file on a path the nodes see
  std::string run_id;          // the workers join only this run
  std::string data_dir;        // dataset root the nodes see ("" = the path each episode names)
  std::string dir;             // job script, worker logs and worker folders (on a shared path)
};

/// The job script that starts one worker (it reads $SLURM_ARRAY_TASK_ID); pure, for tests.
std::string worker_job_script(const SlurmRequest& request);

/// The sbatch argv for `script_path`: ours first (array, name, output, --parsable), the user's
/// after, so theirs win where both set one. @throws mtg::Error for options that do not parse.
std::vector<std::string> sbatch_command(const SlurmRequest& request, const std::string& script_path);

class SlurmWorkers {
 public:
  /// Writes the job script into request.dir and submits it. @throws mtg::Error with sbatch's
  /// message when the submission is refused.
  explicit SlurmWorkers(const SlurmRequest& request);
  /// Cancels the array (whatever is still queued or running).
  ~SlurmWorkers();
  SlurmWorkers(const SlurmWorkers&) = delete;
  SlurmWorkers& operator=(const SlurmWorkers&) = delete;

  const std::string& job_id() const { return job_id_; }

 private:
  std::string job_id_;
};

}  // namespace mtg::orchestrator::remote
