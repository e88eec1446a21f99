#include "sph/generation/generation.h"

#include "sph/generation/dataset_metadata.h"
#include "sph/generation/trajectory_plan.h"
#include "sph/generation/trajectory_simulation.h"

namespace sph {

nlohmann::json generate(const GenerateOptions& o, TrajectorySink& sink) {
  const std::vector<TrajectoryPlan> plan = plan_trajectories(o);
  sink.start(o, plan);
  std::vector<nlohmann::json> described(plan.size());
  for (const TrajectoryPlan& p : plan) {
    const size_t k = size_t(p.index);
    if (std::optional<nlohmann::json> done = sink.finished_before(p)) {
      described[k] = std::move(*done);
      if (o.log) *o.log << "trajectory " << k + 1 << "/" << o.trajectories << ": done before\n";
      continue;
    }
    try {
      described[k] = simulate_trajectory(o, p, sink);
      sink.end(p, described[k]);
    } catch (...) {
      sink.abandon(p);
      throw;
    }
    if (o.log) *o.log << "trajectories: " << k + 1 << "/" << o.trajectories << " done\n";
  }
  const nlohmann::json metadata = dataset_metadata(o, described);
  sink.finish(plan, metadata);
  return metadata;
}

}  // namespace sph
