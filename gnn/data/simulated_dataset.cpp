#include "gnn/data/simulated_dataset.h"

#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include "common/checked_file.h"
#include "common/fnv1a.h"
#include "common/output_folder.h"
#include "sph/generation/dataset_folder.h"
#include "sph/io/tensor_recorder.h"

namespace gnn {
namespace {

namespace fs = std::filesystem;

// The in-process sink: the recorder's tensors, kept in memory. With --save-data it also opens
// the folder they are saved to, once the request is checked and before anything is simulated.
class RecorderSink : public sph::TrajectorySink {
 public:
  RecorderSink(const sph::GenerateOptions& options, std::string save_dir)
      : options_(options), save_dir_(std::move(save_dir)) {}

  void start(const sph::GenerateOptions&, const std::vector<sph::TrajectoryPlan>&) override {
    if (save_dir_.empty()) return;
    // Never replaced: a dataset folder may hold what took hours to simulate.
    if (fs::exists(common::normalise_output_path(save_dir_)))
      throw common::OutputPathError("--save-data " + save_dir_ +
                                    ": already exists; name a new folder");
    common::OutputFolderPolicy policy;
    policy.option = "--save-data";
    policy.markers = {"metadata.json", "train.h5", "valid.h5", "test.h5"};
    policy.inputs = {options_.scene_file};
    policy.log = options_.log;
    saved.emplace(save_dir_, policy);
  }
  std::string interrupted_note(const sph::TrajectoryPlan&) const override {
    return "nothing was saved or trained (the data are simulated first)";
  }
  // Built before the simulation runs, as the generator's file is: particle types are a
  // particle's phase when it was made.
  void begin(const sph::Simulation& sim, const sph::TrajectoryPlan&) override {
    recorder_.emplace(sim, 1);
  }
  void record(const sph::Simulation& sim) override { recorder_->record(sim); }
  void end(const sph::TrajectoryPlan&, const nlohmann::json&) override {
    recorded.push_back(recorder_->take());
    recorder_.reset();
  }
  void finish(const std::vector<sph::TrajectoryPlan>& p, const nlohmann::json&) override {
    plan = p;
  }

  std::vector<sph::TrajectoryPlan> plan;
  std::vector<sph::RecordedTrajectory> recorded;  // in index order
  std::optional<common::OutputFolder> saved;

 private:
  const sph::GenerateOptions& options_;
  std::string save_dir_;
  std::optional<sph::TensorRecorder> recorder_;
};

// FNV-1a over the bytes of tensors.
void add_tensor(common::Fnv1a& hash, const at::Tensor& t) {
  const at::Tensor c = t.contiguous();
  hash.add(c.data_ptr(), size_t(c.numel()) * c.element_size());
}

std::string part_name(int index) {
  std::ostringstream s;
  s << "trajectory_" << std::setw(5) << std::setfill('0') << index << ".h5";
  return s.str();
}

// Writes the dataset files into `folder`: each trajectory as a part file, assembled into the
// split files as the generator assembles its parts, then metadata.json.
void write_dataset(const fs::path& folder, const std::vector<sph::TrajectoryPlan>& plan,
                   const std::vector<sph::RecordedTrajectory>& recorded,
                   const nlohmann::json& metadata) {
  const fs::path parts = folder / "parts";
  fs::create_directories(parts);
  std::vector<fs::path> files;
  for (const auto& p : plan) {
    files.push_back(parts / part_name(p.index));
    sph::write_trajectory(files.back().string(), "00000", recorded[size_t(p.index)]);
  }
  for (int s = 0; s < 3; ++s) {
    std::vector<fs::path> members;
    for (const auto& p : plan)
      if (p.split == s) members.push_back(files[size_t(p.index)]);
    sph::assemble_split(folder / (std::string(sph::split_name(s)) + ".h5"), members);
  }
  fs::remove_all(parts);
  common::write_file_atomically(folder / "metadata.json", metadata.dump(2) + "\n");
}

}  // namespace

SimulatedDataset simulate_dataset(const sph::GenerateOptions& options,
                                  const std::string& save_dir) {
  RecorderSink sink(options, save_dir);
  const nlohmann::json metadata = sph::generate(options, sink).metadata;
  const std::vector<sph::TrajectoryPlan>& plan = sink.plan;
  const std::vector<sph::RecordedTrajectory>& recorded = sink.recorded;
  std::optional<common::OutputFolder>& saved = sink.saved;

  SimulatedDataset out;
  std::string where = options.scene_file + " (simulated in-process)";
  if (saved) {
    write_dataset(saved->staging(), plan, recorded, metadata);
    saved->commit();
    where = (saved->target() / "metadata.json").string();
  }
  out.metadata = metadata_from_json(metadata, where);
  common::Fnv1a hash;
  // metadata.json lists the trajectories split by split; splits are consecutive in index order,
  // but each entry is looked up by its index all the same.
  const nlohmann::json& entries = metadata.at("trajectories");
  for (const auto& p : plan) {
    const sph::RecordedTrajectory& r = recorded[size_t(p.index)];
    for (const at::Tensor* t : {&r.time, &r.position, &r.velocity, &r.active, &r.volume_fraction,
                                &r.particle_type, &r.boundary_position})
      add_tensor(hash, *t);
    int64_t entry = 0;
    while (entries.at(size_t(entry)).at("index") != p.index) ++entry;
    // The scene and materials as read_split gives them for the saved file.
    nlohmann::json scene = trajectory_scene(metadata, entry);
    Trajectory t = from_recorded(r, scene.value("materials", nlohmann::json::object()));
    t.scene = std::move(scene);
    t.source = where + ": trajectory " + std::to_string(p.index) + " (" + sph::split_name(p.split) +
               " " + entries[size_t(entry)].at("group").get<std::string>() + ")";
    t.sph_seconds_per_frame = entries[size_t(entry)].value("sph_seconds_per_frame", 0.0);
    (p.split == 0 ? out.train : p.split == 1 ? out.valid : out.test).push_back(std::move(t));
  }
  out.fingerprint = hash.hex();
  return out;
}

}  // namespace gnn
