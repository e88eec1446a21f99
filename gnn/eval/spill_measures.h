#pragma once
// The oil measures of spill.json on recorded or predicted frames, by the simulator's own code
// (sph::measure_slick and sph::SpillMetrics), so that what `spill-infer eval` and `compare` score
// is exactly what a run's spill.json reports: a particle is oil when its oil fraction is at least
// 1/2, the slick is the top-view cells a particle diameter wide that hold oil.

#include <torch/torch.h>

#include <memory>
#include <optional>

#include "gnn/data/dataset.h"
#include "gnn/eval/rollout.h"
#include "sph/core/particle_set.h"
#include "sph/river/spill_metrics.h"
#include "sph/scene/scene.h"
#include "sph/simulation/density_relaxation.h"

namespace gnn {

// One frame's active particles (positions [N, 3], active [N], oil fractions [N]) as the
// simulator's particle set, every particle of rest volume `particle_volume`; arrays the spill
// measures do not read are zero.
sph::FluidParticles fluid_of_frame(const torch::Tensor& position, const torch::Tensor& active,
                                   const torch::Tensor& oil_fraction, double particle_volume);

// Positions [n, 3] and oil fractions [n] of fluid particles as the simulator's vectors, and back.
std::vector<sph::Vec3> vectors_of(const torch::Tensor& position);
std::vector<sph::Real> reals_of(const torch::Tensor& values);
torch::Tensor tensor_of(const std::vector<sph::Vec3>& vectors);

// A frame correction that moves each learned frame's positions by `iterations` of the
// simulator's constant-density correction (`relaxation` is kept alive by the hook).
FrameCorrection relaxation_correction(std::shared_ptr<sph::DensityRelaxation> relaxation,
                                      int iterations);

// What the scene of a trajectory says about its particles and its river.
class SpillScene {
 public:
  // Throws DatasetError naming `t.source` when the trajectory carries no scene.
  explicit SpillScene(const Trajectory& t);
  double particle_volume() const { return double(sph::particle_rest_volume(scene_)); }
  double cell() const { return double(scene_.particle_diameter()); }  // m
  // Fresh per-frame river spill measures (slick area, front, banks), as spill.json's; null when
  // the scene is not a river with a leak.
  std::unique_ptr<sph::SpillMetrics> river_metrics() const;
  // The names of the scene's watch points (intakes, boom sites), in the scene's order.
  std::vector<std::string> watch_point_names() const;
  // The simulated time (s) the last of the scene's leaks stops; none without leaks.
  std::optional<double> leak_end_time() const;
  // The simulator's constant-density correction for this scene (built on first use).
  sph::DensityRelaxation& relaxation();

 private:
  sph::SceneConfig scene_;
  std::unique_ptr<sph::DensityRelaxation> relaxation_;
};

}  // namespace gnn
