#pragma once
// Data-parallel training over LibTorch's c10d: one spill-train process per rank, launched by
// PyTorch's launcher (`python3 -m torch.distributed.run --no_python ... spill-train ...`) or by
// Slurm's `srun`, joined through a c10d TCPStore and a ProcessGroupGloo. We write no transport,
// rendezvous or scheduler: the launcher starts the processes and sets the variables, c10d
// connects them. LibTorch's C++ API has no DistributedDataParallel, so the gradient averaging
// (an allreduce in buckets after the backward) is ours, on the process group.
//
// Without launch variables (or with a world of one) a run is the plain single-process run.
// Built without Gloo's headers (libgloo-dev), a launch with a world above one is refused.

#include <torch/torch.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

namespace train {

// Where this process stands in a launch: from torchrun's RANK, WORLD_SIZE, LOCAL_RANK,
// MASTER_ADDR, MASTER_PORT (and its agent's store), else from Slurm's SLURM_PROCID,
// SLURM_NTASKS, SLURM_LOCALID with MASTER_ADDR and MASTER_PORT given.
struct LaunchEnvironment {
  int rank = 0, world = 1, local_rank = 0;
  std::string master_addr;
  int master_port = 0;
  // torchrun's agent already serves a TCPStore at MASTER_PORT: the ranks join it as clients,
  // under the prefix /worker/attempt_<restart> (as PyTorch's env:// does).
  bool agent_store = false;
  int restart = 0;
  std::string launcher;  // "torchrun", "slurm" or "" (none)
};

// Reads the environment. Throws common::InputError naming the variable for a malformed one, or
// for a world above one without MASTER_ADDR or MASTER_PORT.
LaunchEnvironment read_launch_environment();

class DataParallel {
 public:
  // Joins the process group of `launch` (world > 1); every collective fails after `timeout`
  // without its peers. Throws common::InputError when this build has no Gloo.
  static std::unique_ptr<DataParallel> connect(const LaunchEnvironment& launch,
                                               std::chrono::milliseconds timeout);
  ~DataParallel();
  DataParallel(const DataParallel&) = delete;
  DataParallel& operator=(const DataParallel&) = delete;

  int rank() const { return rank_; }
  int world() const { return world_; }

  // The sum over the ranks of each rank's values (in place), one allreduce.
  void sum(std::vector<double>& values);
  // grad := sum over ranks of (weight_r * grad_r) for every parameter with a gradient, as
  // allreduces of flat buckets of at most `bucket_bytes`.
  void sum_weighted_gradients(const std::vector<torch::Tensor>& parameters, double weight);
  // Every rank's tensors become rank 0's (initial weights, batch-normalisation statistics).
  void broadcast_from_first(const std::vector<torch::Tensor>& tensors);
  // Seconds one allreduce of `floats` numbers takes, the median of `repeats` (the benchmark).
  double time_allreduce(int64_t floats, int repeats);

  static constexpr int64_t kBucketBytes = 25 << 20;  // as PyTorch's DistributedDataParallel

 private:
  struct Group;
  DataParallel(int rank, int world, std::unique_ptr<Group> group);
  void run(const char* what, const std::function<void()>& collective);
  int rank_ = 0, world_ = 1;
  std::unique_ptr<Group> group_;
};

}  // namespace train
