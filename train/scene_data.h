#pragma once
// `spill-train --scene`: the run's training data simulated in the training process
// (gnn/data/simulated_dataset.h), as `spill-sim generate` would simulate them for the same
// options, optionally saved as a dataset folder (--save-data).
//
// --resume re-simulates them from the same seed and options, and goes on only when the data are
// bit-identical to those the run trained on (RUN/config.json keeps their fingerprint): a
// simulation on more than one thread is not bit-reproducible, and is then refused with a message
// that says so.

#include <string>

#include "sph/generation/generation.h"
#include "train/trainer.h"

namespace train {

struct SceneDataOptions {
  sph::GenerateOptions generate;  // the scene and the spill-sim generate options
  std::string save_dir;           // --save-data: also write the dataset here; empty for none
};

// Simulates the data of `options` for the run of `run` (its out_dir and resume flag). The
// description names the scene, the generation settings and the data's fingerprint. Throws
// common::InputError for bad input before simulating, and for a resumed run whose stored
// description differs or whose re-simulated data are not identical.
TrainingData simulate_training_data(const SceneDataOptions& options, const TrainerOptions& run);

}  // namespace train
