#include "sph/boundary/emitter.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sph {

Emitter::Emitter(const EmitterConfig& config, Real spacing, Real volume, const PhaseMix& mix)
    : config_(config), direction_(config.direction.normalized()), volume_(volume), mix_(mix) {
  // An orthonormal basis (u, w) of the outlet plane; u is horizontal when it can be.
  Vec3 u = direction_.cross(Vec3(0, 0, 1));
  if (u.norm() < Real(1e-6)) u = direction_.cross(Vec3(1, 0, 0));
  u.normalize();
  const Vec3 w = direction_.cross(u).normalized();
  if (config.shape == "disc") {
    const int n = int(std::ceil(config.radius / spacing));
    for (int i = -n; i <= n; ++i)
      for (int j = -n; j <= n; ++j) {
        const Real a = Real(i) * spacing, b = Real(j) * spacing;
        if (a * a + b * b <= config.radius * config.radius + Real(1e-6) * spacing * spacing)
          layer_.push_back(config.centre + a * u + b * w);
      }
  } else {
    const int nu = std::max(1, int(std::floor(config.width / spacing + Real(1e-4))));
    const int nw = std::max(1, int(std::floor(config.height / spacing + Real(1e-4))));
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nw; ++j)
        layer_.push_back(config.centre + (Real(i) - Real(nu - 1) / 2) * spacing * u +
                         (Real(j) - Real(nw - 1) / 2) * spacing * w);
  }
  const double duration = double(config.stop) - double(config.start);
  // Whole particles, not whole layers: rate x duration rounded to the nearest particle (a leak's
  // volume is what a responder reads first; whole layers of a 30-particle outlet were 6 % off).
  // In double first: a huge rate once wrapped the 32-bit count to zero and emitted nothing.
  const double particles =
      std::max(1.0, std::round(double(config.rate) * duration / double(volume)));
  if (!(particles <= kMaxEmittedParticles))
    throw EmitterRateError("a rate of " + std::to_string(config.rate) + " m^3/s for " +
                           std::to_string(duration) + " s releases " + std::to_string(particles) +
                           " particles; at most 1e8 are allowed per outlet");
  particles_ = Index(particles);
  const Index per_layer = Index(layer_.size());
  layers_ = (particles_ + per_layer - 1) / per_layer;
  // The last layer holds the remainder, on sites spread evenly over the outlet.
  const Index last = particles_ - (layers_ - 1) * per_layer;
  for (Index j = 0; j < last; ++j)
    last_sites_.push_back(Index(std::floor((double(j) + 0.5) * double(per_layer) / double(last))));
  // Full layers leave at the cadence of the rate; the partial last one keeps that cadence (up to
  // half an interval after the stop when it holds under half a layer), so no layer ever comes
  // closer than a full interval behind the one before.
  interval_ = duration * double(per_layer) / double(particles_);
  // A layer must have moved one spacing before the next one appears on top of it; slower
  // outflow would stack layers closer than the rest spacing and the pressure solve would blast
  // them apart.
  const double min_speed = double(spacing) / interval_;
  if (double(config.speed) < min_speed * (1 - 1e-6))
    throw std::invalid_argument(
        "a rate of " + std::to_string(config.rate) + " m^3/s through this outlet (" +
        std::to_string(layer_.size()) + " particles per layer) needs a speed of at least " +
        std::to_string(min_speed) + " m/s, got " + std::to_string(config.speed) + " m/s");
}

void Emitter::allocate(FluidParticles& fluid) {
  first_id_ = fluid.size();
  const Vec3 velocity = config_.speed * direction_;
  const Index per_layer = Index(layer_.size());
  for (Index k = 0; k < capacity(); ++k)
    fluid.add(layer_[site(k / per_layer, k % per_layer)], velocity, volume_, mix_,
              /*active=*/false);
}

double Emitter::due(Index layer) const {
  const double start = double(config_.start);
  // A single, partial layer leaves in the middle of the release.
  if (layers_ == 1) return start + 0.5 * (double(config_.stop) - start);
  return start + (double(layer) + 0.5) * interval_;
}

Index Emitter::layers_due(double t) const {
  if (layers_ == 1) return due(0) <= t ? 1 : 0;
  // Layer k leaves at start + (k + 1/2) interval (see due): the count follows without a loop.
  const double layers = std::floor((t - double(config_.start)) / interval_ + 0.5 + 1e-9);
  return Index(std::clamp(layers, 0.0, double(layers_)));
}

void Emitter::emit(FluidParticles& fluid, double t) {
  const Vec3 velocity = config_.speed * direction_;
  while (emitted_layers_ < layers_) {
    // Each layer carries the volume of one interval and leaves at its middle, so the released
    // volume never differs from rate x elapsed time by more than half a layer.
    const double leaves = due(emitted_layers_);
    if (leaves > t) break;
    const Real travelled = Real(t - leaves) * config_.speed;
    for (Index k = 0; k < layer_count(emitted_layers_); ++k) {
      const Index id = first_id_ + emitted_layers_ * Index(layer_.size()) + k;
      fluid.activate(fluid.find_inactive(id),
                     layer_[site(emitted_layers_, k)] + travelled * direction_, velocity);
    }
    ++emitted_layers_;
  }
}

}  // namespace sph
