#pragma once
// The per-frame outputs of a run folder, written from a Simulation's state: trajectory.h5 (the
// data contract), PLY and VTK frames and pictures on request, and spill.json with spill.svg (a
// river leak's spill metrics, or the slick's shape of oil on still water). `spill-sim run` and
// `spill-infer predict` both record through it, so their folders read the same.

#include <filesystem>
#include <memory>

#include "common/image_writer.h"
#include "common/picture_annotation.h"
#include "sph/io/trajectory_writer.h"
#include "sph/io/vtk_writer.h"
#include "sph/river/spill_metrics.h"
#include "sph/scene/scene.h"
#include "sph/simulation/simulation.h"

namespace sph {

struct RecorderOptions {
  bool png = false;  // side-, top- (and river-) view pictures of every frame in png/
  bool ply = false;  // PLY frames in ply/ (and ply/boundary.ply once)
  // VTK (ParaView) point files in vtk/: a frame each, vtk/fluid.pvd listing them with their
  // times, vtk/boundary.vtp once
  bool vtk = false;
  // Whether density and pressure come from a solver. A learned simulator's frames
  // (Simulation::apply_external_frame) leave them stale, so vtk/ then leaves them out.
  bool solver_state = true;
};

class RunRecorder {
 public:
  // Writes into `folder` (which exists; png/, ply/ and vtk/ are made as needed).
  RunRecorder(const Simulation& sim, const SceneConfig& scene, RecorderOptions options,
              const std::filesystem::path& folder);

  // Appends the simulation's current state as frame `frame` (its number in file names).
  void record(const Simulation& sim, int frame);
  void close_trajectory() { writer_.close(); }
  // spill.json and spill.svg, for a scene with either kind of metrics.
  void write_metrics() const;

 private:
  const SceneConfig& scene_;
  RecorderOptions options_;
  std::filesystem::path folder_;
  TrajectoryWriter writer_;
  std::unique_ptr<common::FrameRenderer> renderer_;
  common::PictureAnnotation annotation_;
  std::unique_ptr<SpillMetrics> spill_;
  std::unique_ptr<StillWaterSlickMetrics> slick_;
  std::unique_ptr<VtkSeries> vtk_;  // with options_.vtk
};

}  // namespace sph
