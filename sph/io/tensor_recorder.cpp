#include "sph/io/tensor_recorder.h"

#include <ATen/Parallel.h>
#include <omp.h>

#include "sph/core/config.h"
#include "sph/io/trajectory_writer.h"

namespace sph {

namespace {

at::Tensor vectors_tensor(const std::vector<Vec3>& v) {
  at::Tensor t = at::empty({long(v.size()), 3}, at::kFloat);
  float* p = t.data_ptr<float>();
  for (size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) p[3 * i + size_t(k)] = float(v[i][k]);
  return t;
}

}  // namespace

TensorRecorder::TensorRecorder(const Simulation& sim, int frame_stride)
    : stride_(std::max(1, frame_stride)) {
  const int threads = omp_get_max_threads();
  const FluidParticles& f = sim.fluid();
  particle_type_ = at::empty({long(f.size())}, at::kInt);
  for (Index i = 0; i < f.size(); ++i)
    particle_type_.data_ptr<std::int32_t>()[f.id[i]] = std::int32_t(f.type[i]);
  boundary_ = vectors_tensor(sim.boundary().position);
  // The operations above were LibTorch's first: give OpenMP back its thread count.
  at::set_num_threads(threads);
}

void TensorRecorder::record(const Simulation& sim) {
  if (offered_++ % stride_ != 0) return;
  const FluidParticles& f = sim.fluid();
  const long n = long(f.size());
  at::Tensor active = at::zeros({n}, at::kByte);
  for (Index i = 0; i < f.active_count(); ++i) active.data_ptr<std::uint8_t>()[f.id[i]] = 1;
  at::Tensor fraction = at::empty({n}, at::kFloat);
  for (Index i = 0; i < f.size(); ++i)
    fraction.data_ptr<float>()[f.id[i]] = float(f.oil_fraction[i]);
  time_.push_back(sim.time());
  position_.push_back(vectors_tensor(sim.in_id_order(f.position)));
  velocity_.push_back(vectors_tensor(sim.in_id_order(f.velocity)));
  active_.push_back(active);
  fraction_.push_back(fraction);
}

RecordedTrajectory TensorRecorder::take() {
  if (time_.empty()) throw std::logic_error("TensorRecorder::take: no frames recorded");
  RecordedTrajectory t;
  t.time = at::empty({long(time_.size())}, at::kDouble);
  std::copy(time_.begin(), time_.end(), t.time.data_ptr<double>());
  t.position = at::stack(position_);
  t.velocity = at::stack(velocity_);
  t.active = at::stack(active_);
  t.volume_fraction = at::stack(fraction_);
  t.particle_type = particle_type_.clone();
  t.boundary_position = boundary_.clone();
  time_.clear();
  position_.clear();
  velocity_.clear();
  active_.clear();
  fraction_.clear();
  return t;
}

void write_trajectory(const std::string& file, const std::string& group,
                      const RecordedTrajectory& t) {
  const long frames = t.time.size(0), n = t.particle_type.size(0);
  std::vector<std::int32_t> types(t.particle_type.data_ptr<std::int32_t>(),
                                  t.particle_type.data_ptr<std::int32_t>() + n);
  std::vector<Vec3> boundary(size_t(t.boundary_position.size(0)));
  const float* b = t.boundary_position.data_ptr<float>();
  for (size_t i = 0; i < boundary.size(); ++i)
    boundary[i] = Vec3(Real(b[3 * i]), Real(b[3 * i + 1]), Real(b[3 * i + 2]));
  TrajectoryWriter writer(file, group, types, boundary);
  const at::Tensor position = t.position.contiguous(), velocity = t.velocity.contiguous(),
                   active = t.active.contiguous(), fraction = t.volume_fraction.contiguous();
  for (long k = 0; k < frames; ++k)
    writer.append(t.time.data_ptr<double>()[k], position[k].data_ptr<float>(),
                  velocity[k].data_ptr<float>(), active[k].data_ptr<std::uint8_t>(),
                  fraction[k].data_ptr<float>());
  writer.close();
}

}  // namespace sph
