#pragma once
// Training data simulated in the training process (`spill-train --scene`): the trajectories that
// `spill-sim generate` writes for the same request (sph/generation/generation.h: the same draws
// from the seed, splits, warm-up rule, normalisation statistics and metadata), recorded into
// tensors by the tensor recorder and handed over without an HDF5 round trip. Optionally also
// saved as a dataset folder that `--data` and spill-infer read like a generated one.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gnn/data/dataset.h"
#include "sph/generation/generation.h"

namespace gnn {

struct SimulatedDataset {
  // metadata.json's content as spill-sim generate writes it (raw), checked as read_metadata
  // checks a file; `file` is the saved metadata.json, or names the scene.
  DatasetMetadata metadata;
  std::vector<Trajectory> train, valid, test;  // in their order in the split files
  // FNV-1a (64 bits, hex) of every trajectory's recorded tensors (time, position, velocity,
  // active, volume fraction, particle type, boundary) in index order: equal only for identical
  // data (a resumed run checks that its re-simulated data are the ones it trained on).
  std::string fingerprint;
};

// Simulates every trajectory of `options` (options.out_dir is not used; options.log, when set,
// gets a progress line per trajectory). With `save_dir` non-empty the trajectories are also
// written there as a dataset: metadata.json, train.h5, valid.h5 and test.h5, the files
// spill-sim generate writes, the folder appearing whole once everything is simulated; an existing
// folder is refused. Bad input (scene file, --vary pointer, counts, --save-data folder) throws
// common::InputError before anything is simulated or written.
SimulatedDataset simulate_dataset(const sph::GenerateOptions& options,
                                  const std::string& save_dir = "");

}  // namespace gnn
