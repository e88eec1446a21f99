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

// The in-process sink: the recorder's tensors, kept in memory. With --save-data it tees every
// trajectory to spill-sim generate's own folder sink, writing into a folder it opens once the
// request is checked and before anything is simulated.
class RecorderSink : public sph::TrajectorySink {
 public:
  RecorderSink(const sph::GenerateOptions& options, std::string save_dir)
      : options_(options), save_dir_(std::move(save_dir)) {}

  void start(const sph::GenerateOptions& o, const std::vector<sph::TrajectoryPlan>& p) override {
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
    folder_ = sph::dataset_folder_sink(saved->staging());
    folder_->start(o, p);
  }
  std::string interrupted_note(const sph::TrajectoryPlan&) const override {
    return "nothing was saved or trained (the data are simulated first)";
  }
  // Built before the simulation runs, as the generator's file is: particle types are a
  // particle's phase when it was made.
  void begin(const sph::Simulation& sim, const sph::TrajectoryPlan& p) override {
    recorder_.emplace(sim, 1);
    if (folder_) folder_->begin(sim, p);
  }
  void record(const sph::Simulation& sim) override {
    recorder_->record(sim);
    if (folder_) folder_->record(sim);
  }
  void end(const sph::TrajectoryPlan& p, const nlohmann::json& description) override {
    recorded.push_back(recorder_->take());
    recorder_.reset();
    if (folder_) folder_->end(p, description);
  }
  void abandon(const sph::TrajectoryPlan& p) override {
    if (folder_) folder_->abandon(p);
  }
  void finish(const std::vector<sph::TrajectoryPlan>& p, const nlohmann::json& metadata) override {
    plan = p;
    if (!folder_) return;
    folder_->finish(p, metadata);
    // The dataset's files only: the parts that let a generation resume have no use here.
    fs::remove_all(saved->staging() / "parts");
  }

  std::vector<sph::TrajectoryPlan> plan;
  std::vector<sph::RecordedTrajectory> recorded;  // in index order
  std::optional<common::OutputFolder> saved;

 private:
  const sph::GenerateOptions& options_;
  std::string save_dir_;
  std::optional<sph::TensorRecorder> recorder_;
  std::unique_ptr<sph::TrajectorySink> folder_;  // --save-data's dataset folder
};

// FNV-1a over the bytes of tensors.
void add_tensor(common::Fnv1a& hash, const at::Tensor& t) {
  const at::Tensor c = t.contiguous();
  hash.add(c.data_ptr(), size_t(c.numel()) * c.element_size());
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
