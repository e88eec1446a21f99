#pragma once
// A run folder of spill-sim run or spill-infer predict read through the dataset reader (the data
// contract): the folder's metadata.json with neutral normalisation statistics, and its
// trajectory.h5 as the test split of a one-trajectory dataset in `view`.
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "gnn/data/dataset.h"

namespace run_folder {

struct Read {
  gnn::DatasetMetadata metadata;
  gnn::Trajectory trajectory;
};

inline Read read(const std::filesystem::path& run, const std::filesystem::path& view) {
  namespace fs = std::filesystem;
  fs::create_directories(view);
  nlohmann::json meta;
  std::ifstream(run / "metadata.json") >> meta;
  meta["vel_mean"] = meta["acc_mean"] = {0, 0, 0};
  meta["vel_std"] = meta["acc_std"] = {1, 1, 1};
  std::ofstream(view / "metadata.json") << meta.dump();
  fs::copy_file(run / "trajectory.h5", view / "test.h5", fs::copy_options::overwrite_existing);
  Read r;
  r.metadata = gnn::read_metadata((view / "metadata.json").string());
  auto split = gnn::read_split(view.string(), "test", r.metadata);
  r.trajectory = std::move(split.at(0));
  return r;
}

}  // namespace run_folder
