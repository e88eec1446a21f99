#pragma once
// A checkpoint and the split it is to be run on, checked against each other before any output
// is written: the data must have the dimension, particle types, particle radius and
// connectivity radius the model was trained with.

#include <filesystem>
#include <vector>

#include "common/output_folder.h"
#include "gnn/data/dataset.h"
#include "gnn/runtime/runtime.h"
#include "gnn/training/checkpoint.h"
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
  d.checkpoint.simulator->to(gnn::parse_device(o.device));
  d.checkpoint.simulator->model().eval();
  // The thread split for this model, unless --blas-threads gave one.
  const gnn::GraphModel& model = d.checkpoint.simulator->model();
  const gnn::RuntimeSettings mix =
      o.blas_threads > 0 ? gnn::RuntimeSettings{o.threads, o.blas_threads}
                         : gnn::inference_runtime(o.threads, model.infers_on_one_blas_thread());
  gnn::configure_runtime(mix);
  if (o.log)
    *o.log << "threads: " << mix.threads << " LibTorch, " << mix.blas_threads << " BLAS"
           << (o.blas_threads > 0 ? " (as asked)"
                                  : " (the measured best split for " + model.name() + ")")
           << "\n";
  return d;
}

// The command's output folder: staged beside OUT and renamed into place at the end; an existing
// OUT is replaced only when it holds `markers` (an earlier output of the same command).
inline common::OutputFolderPolicy output_policy(const CommonOptions& o,
                                                std::vector<std::string> markers) {
  common::OutputFolderPolicy policy;
  policy.markers = std::move(markers);
  policy.replace = true;
  policy.inputs = {o.checkpoint, o.data_dir};
  policy.log = o.log;
  return policy;
}

}  // namespace infer
