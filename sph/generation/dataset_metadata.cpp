#include "sph/generation/dataset_metadata.h"

#include <stdexcept>

#include "sph/generation/moments.h"
#include "sph/generation/trajectory_plan.h"
#include "sph/io/run_metadata.h"
#include "sph/simulation/simulation.h"

namespace sph {

nlohmann::json dataset_metadata(const GenerateOptions& o,
                                const std::vector<nlohmann::json>& trajectories) {
  if (trajectories.empty()) throw std::invalid_argument("dataset_metadata: no trajectories");
  // Normalisation statistics over the training split (all trajectories if it is empty).
  bool any_train = false;
  for (const auto& t : trajectories) any_train = any_train || t.at("split") == "train";
  Moments velocity, acceleration;
  for (const auto& t : trajectories)
    if (t.at("split") == "train" || !any_train) {
      velocity.add(Moments::from_json(t.at("velocity_moments")));
      acceleration.add(Moments::from_json(t.at("acceleration_moments")));
    }
  nlohmann::json lengths = nlohmann::json::object(), split_counts_json = nlohmann::json::object();
  nlohmann::json described = nlohmann::json::array();
  for (int s = 0; s < 3; ++s) {
    int members = 0;
    lengths[split_name(s)] = nlohmann::json::array();
    for (const auto& info : trajectories)
      if (info.at("split") == split_name(s)) {
        nlohmann::json t = info;
        t.erase("velocity_moments");
        t.erase("acceleration_moments");
        t["group"] = group_name(members++);
        described.push_back(t);
        lengths[split_name(s)].push_back(info.at("frames"));
      }
    split_counts_json[split_name(s)] = members;
  }
  const LoadedScene base = trajectory_scene(o, trajectories[0].at("parameters"));
  const Simulation base_sim(base.config);
  nlohmann::json meta = run_metadata(base_sim, base, int(trajectories[0].at("frames")) - 1);
  meta["sequence_length"] = trajectories[0].at("frames");
  meta["sequence_lengths"] = lengths;
  meta["counts"] = split_counts_json;
  meta["vel_mean"] = velocity.mean();
  meta["vel_std"] = velocity.std_dev();
  meta["acc_mean"] = acceleration.mean();
  meta["acc_std"] = acceleration.std_dev();
  meta["statistics_note"] =
      "velocity x_t - x_(t-1) and acceleration x_(t+1) - 2 x_t + x_(t-1) per frame (m), over "
      "fluid particles active in those frames, of the training split";
  meta["generation"] = generation_settings(o);
  meta["trajectories"] = described;
  return meta;
}

}  // namespace sph
