#pragma once
// The pipeline's last step: metadata.json of a dataset from its trajectories' descriptions.

#include <nlohmann/json.hpp>
#include <vector>

#include "sph/generation/generation.h"

namespace sph {

// metadata.json of a dataset from the descriptions simulate_trajectory returned for every
// trajectory, in index order: the run metadata of the first trajectory's scene, sequence lengths
// and counts per split, the normalisation statistics over the training split (every trajectory
// when it is empty), the generation settings, and each trajectory's description without its
// moments and with its group in its split's file.
nlohmann::json dataset_metadata(const GenerateOptions& options,
                                const std::vector<nlohmann::json>& trajectories);

}  // namespace sph
