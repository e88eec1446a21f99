#pragma once
// Releases fluid through a disc or rectangle: every `interval` seconds one layer of particles
// (a lattice of the particle spacing covering the outlet) is activated at the outlet plane and
// given the outflow velocity. The particles exist from the start as inactive members of the
// fluid set (fixed identities, so trajectories keep a constant N with an `active` mask). The
// number of particles is rate x duration rounded to a whole particle, so the released volume is
// right to half a particle; they leave in full layers spread evenly over the duration, the last
// layer holding the remainder on sites spread over the outlet.

#include <stdexcept>
#include <vector>

#include "sph/boundary/boundary_configs.h"
#include "sph/core/particle_set.h"

namespace sph {

// An outlet whose rate over its duration would release more particles than a run can hold.
class EmitterRateError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// The most particles one emitter may release: far beyond any scene we run (a few 10^5), well
// inside the 32-bit particle index, so the count can never wrap.
constexpr double kMaxEmittedParticles = 1e8;

class Emitter {
 public:
  // `volume` is a particle's rest volume, `spacing` the particle diameter. Throws
  // std::invalid_argument when the speed is too low to carry the rate through the outlet.
  Emitter(const EmitterConfig& config, Real spacing, Real volume, const PhaseMix& mix);

  // Appends this emitter's particles, inactive, to `fluid` (call once, before the run).
  void allocate(FluidParticles& fluid);
  // Activates the layers due by time t. Each particle is placed where a layer released at its
  // due time would be now (advected along the outflow), so emission does not depend on dt.
  void emit(FluidParticles& fluid, double t);

  Index capacity() const { return particles_; }
  // Particles released so far.
  Index emitted() const {
    return emitted_layers_ == layers_ ? particles_ : Index(layer_.size()) * emitted_layers_;
  }
  Index emitted_layers() const { return emitted_layers_; }
  // Continues from a saved state in which `layers` layers had been released.
  void restore(Index layers) { emitted_layers_ = std::min(layers, layers_); }
  // Oil volume released so far (m^3).
  double oil_released() const {
    return double(emitted()) * double(volume_) * double(mix_.oil_fraction);
  }
  const std::vector<Vec3>& layer() const { return layer_; }  // outlet points, world coordinates
  // The layer (0 .. layers - 1) particle `id` leaves in; -1 when the emitter does not own it.
  long layer_of(Index id) const {
    if (id < first_id_ || id >= first_id_ + capacity()) return -1;
    return long((id - first_id_) / Index(layer_.size()));
  }
  // How many layers are due by time t (a solver run has released them by its step at t).
  Index layers_due(double t) const;

 private:
  EmitterConfig config_;
  Vec3 direction_;
  Real volume_;
  PhaseMix mix_;
  std::vector<Vec3> layer_;
  // When layer k leaves the outlet (s).
  double due(Index layer) const;
  // Particles of layer k, and the outlet site of its j-th particle.
  Index layer_count(Index k) const {
    return k + 1 == layers_ ? Index(last_sites_.size()) : Index(layer_.size());
  }
  Index site(Index k, Index j) const { return k + 1 == layers_ ? last_sites_[j] : j; }

  Index particles_ = 0;
  std::vector<Index> last_sites_;  // outlet sites of the last layer's particles
  Index layers_ = 0;
  Index emitted_layers_ = 0;
  double interval_ = 0;
  Index first_id_ = 0;
};

}  // namespace sph
