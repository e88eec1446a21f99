#include "gnn/eval/spill_measures.h"

#include <algorithm>

#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"
#include "sph/simulation/spill_measurement.h"

namespace gnn {

sph::FluidParticles fluid_of_frame(const torch::Tensor& position, const torch::Tensor& active,
                                   const torch::Tensor& oil_fraction, double particle_volume) {
  const auto ids = active.nonzero().view(-1);
  const auto x = position.index_select(0, ids).to(torch::kFloat64).contiguous();
  const auto a = oil_fraction.index_select(0, ids).to(torch::kFloat64).contiguous();
  const auto n = sph::Index(ids.size(0));
  sph::FluidParticles f;
  f.for_each_array([&](const char*, auto& values, bool) { values.resize(size_t(n)); });
  const double* xp = x.data_ptr<double>();
  const double* ap = a.data_ptr<double>();
  for (sph::Index i = 0; i < n; ++i) {
    f.position[size_t(i)] =
        sph::Vec3(sph::Real(xp[3 * i]), sph::Real(xp[3 * i + 1]), sph::Real(xp[3 * i + 2]));
    f.velocity[size_t(i)] = sph::Vec3::Zero();
    f.acceleration[size_t(i)] = sph::Vec3::Zero();
    f.oil_fraction[size_t(i)] = sph::Real(ap[i]);
    f.rest_volume[size_t(i)] = sph::Real(particle_volume);
    f.id[size_t(i)] = i;
  }
  f.active = n;
  return f;
}

SpillScene::SpillScene(const Trajectory& t) {
  if (!t.scene.is_object() || t.scene.empty())
    throw DatasetError(t.source +
                       ": the dataset's metadata.json has no \"scene\" to measure the spill with");
  scene_ = sph::parse_scene(t.scene, t.source + " (the dataset's scene)").config;
}

std::unique_ptr<sph::SpillMetrics> SpillScene::river_metrics() const {
  return sph::river_spill_metrics(scene_);
}

std::vector<std::string> SpillScene::watch_point_names() const {
  std::vector<std::string> names;
  for (const auto& w : scene_.watch_points) names.push_back(w.name);
  return names;
}

std::optional<double> SpillScene::leak_end_time() const {
  std::optional<double> end;
  for (const auto& leak : scene_.leaks)
    end = std::max(end.value_or(0.0), double(leak.start + leak.duration));
  return end;
}

sph::DensityRelaxation& SpillScene::relaxation() {
  if (!relaxation_) relaxation_ = std::make_unique<sph::DensityRelaxation>(scene_);
  return *relaxation_;
}

FrameCorrection relaxation_correction(std::shared_ptr<sph::DensityRelaxation> relaxation,
                                      int iterations) {
  return [relaxation, iterations](torch::Tensor& position, const torch::Tensor& fraction) {
    auto x = vectors_of(position);
    relaxation->relax(x, reals_of(fraction), iterations);
    position = tensor_of(x);
  };
}

std::vector<sph::Vec3> vectors_of(const torch::Tensor& position) {
  const auto x = position.to(torch::kFloat64).contiguous();
  const double* p = x.data_ptr<double>();
  std::vector<sph::Vec3> out(size_t(x.size(0)));
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = sph::Vec3(sph::Real(p[3 * i]), sph::Real(p[3 * i + 1]), sph::Real(p[3 * i + 2]));
  return out;
}

std::vector<sph::Real> reals_of(const torch::Tensor& values) {
  const auto v = values.to(torch::kFloat64).contiguous();
  const double* p = v.data_ptr<double>();
  return std::vector<sph::Real>(p, p + v.numel());
}

torch::Tensor tensor_of(const std::vector<sph::Vec3>& vectors) {
  auto out = torch::empty({int64_t(vectors.size()), 3});
  float* p = out.data_ptr<float>();
  for (size_t i = 0; i < vectors.size(); ++i)
    for (int k = 0; k < 3; ++k) p[3 * i + size_t(k)] = float(vectors[i][k]);
  return out;
}

}  // namespace gnn
