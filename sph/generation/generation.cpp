#include "sph/generation/generation.h"

#include "common/exit_codes.h"

#include "sph/generation/dataset_metadata.h"
#include "sph/generation/trajectory_plan.h"
#include "sph/generation/trajectory_simulation.h"

namespace sph {

GenerationResult generate(const GenerateOptions& o, TrajectorySink& sink) {
  const GenerationShard& shard = o.shard;
  if (shard.count < 1 || shard.index < 0 || shard.index >= shard.count)
    throw common::InputError("shard " + std::to_string(shard.index) + "/" +
                             std::to_string(shard.count) + ": expected I/N with 0 <= I < N");
  const std::vector<TrajectoryPlan> plan = plan_trajectories(o);
  sink.start(o, plan);
  auto mine = [&](const TrajectoryPlan& p) {
    return !shard.assemble_only && p.index % shard.count == shard.index;
  };
  GenerationResult result;
  std::vector<nlohmann::json> described(plan.size());
  for (const TrajectoryPlan& p : plan) {
    const size_t k = size_t(p.index);
    if (std::optional<nlohmann::json> done = sink.finished_before(p)) {
      described[k] = std::move(*done);
      if (o.log && mine(p))
        *o.log << "trajectory " << k + 1 << "/" << o.trajectories << ": done before\n";
      continue;
    }
    if (!mine(p)) continue;
    try {
      described[k] = simulate_trajectory(o, p, sink);
      sink.end(p, described[k]);
    } catch (...) {
      sink.abandon(p);
      throw;
    }
    ++result.simulated;
    if (o.log) *o.log << "trajectories: " << k + 1 << "/" << o.trajectories << " done\n";
  }
  // Other shards may have finished theirs while this one ran: whichever shard finds every
  // trajectory finished assembles the dataset.
  for (const TrajectoryPlan& p : plan)
    if (described[size_t(p.index)].is_null()) {
      if (std::optional<nlohmann::json> done = sink.finished_before(p))
        described[size_t(p.index)] = std::move(*done);
      else
        result.missing.push_back(p.index);
    }
  if (!result.missing.empty()) return result;
  result.metadata = dataset_metadata(o, described);
  sink.finish(plan, result.metadata);
  return result;
}

}  // namespace sph
