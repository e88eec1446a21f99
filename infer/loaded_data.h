#pragma once
// A checkpoint and the split it is to be run on, checked against each other before any output
// is written: the data must have the dimension, particle types, particle radius and
// connectivity radius the model was trained with.

#include <filesystem>
#include <vector>

#include "gnn/checkpoint.h"
#include "gnn/dataset.h"
#include "infer/commands.h"

namespace infer {

struct LoadedData {
  gnn::DatasetMetadata metadata;
  std::vector<gnn::Trajectory> trajectories;
  gnn::LoadedCheckpoint checkpoint;
};

inline LoadedData load_data(const CommonOptions& o) {
  LoadedData d;
  d.checkpoint = gnn::load_checkpoint(o.checkpoint);
  d.metadata = gnn::read_metadata((std::filesystem::path(o.data_dir) / "metadata.json").string());
  gnn::check_data_fits(d.checkpoint.data, d.metadata, o.checkpoint);
  d.trajectories = gnn::read_split(o.data_dir, o.split, d.metadata);
  d.checkpoint.simulator->model().eval();
  return d;
}

}  // namespace infer
