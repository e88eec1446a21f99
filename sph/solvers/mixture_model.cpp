#include "sph/solvers/mixture_model.h"

#include <algorithm>
#include <cmath>

#include "sph/core/particle_loops.h"

namespace sph {

namespace {

// Bound on |g - Dv/Dt| in units of |g|: splashes and impacts reach hundreds of g for a step,
// which is a numerical transient, not a settling force.
constexpr Real kMaxSlipInG = 3;
// A phase fraction below this carries no drift momentum (u_k = J_k / alpha_k is undefined).
constexpr Real kTinyFraction = Real(1e-4);
constexpr Index kNoParticle = ~Index(0);

}  // namespace

MixtureModel::MixtureModel(const MixtureConfig& config, const MaterialsConfig& materials,
                           const Vec3& gravity)
    : config_(config), materials_(materials), gravity_(gravity) {}

void MixtureModel::resize(size_t size) {
  if (is_interface_.size() == size) return;
  is_interface_.resize(size, 0);
  flux_oil_.resize(size, Vec3::Zero());
  drift_stress_.resize(size);
  fraction_change_.resize(size, 0);
  limit_oil_.resize(size, 1);
  limit_water_.resize(size, 1);
  step_start_velocity_.resize(size, Vec3::Zero());
  step_start_id_.resize(size, kNoParticle);
  velocity_rate_.resize(size, Vec3::Zero());
}

void MixtureModel::permute(const std::vector<Index>& order) {
  std::vector<Vec3> scratch;
  permute_array(step_start_velocity_, order, scratch);
  permute_array(velocity_rate_, order, scratch);
  std::vector<Index> ids;
  permute_array(step_start_id_, order, ids);
}

Vec3 MixtureModel::slip_acceleration(const FluidParticles& fluid, Index i) const {
  Vec3 a = gravity_;
  // The rate was recorded for the particle whose id is step_start_id_; a slot taken over since
  // (emission, retirement) has none.
  if (step_start_id_[i] == fluid.id[i]) a -= velocity_rate_[i];
  const Real limit = kMaxSlipInG * std::max(gravity_.norm(), Real(1));
  const Real norm = a.norm();
  return norm > limit ? Vec3(a * (limit / norm)) : a;
}

void MixtureModel::compute_drift(const FluidParticles& fluid, const ParticleNeighbourhood& nb) {
  resize(fluid.size());
  const long n = long(fluid.active_count());
  // Clear last step's fluxes (only interface particles had any).
  for (Index i : interface_) {
    flux_oil_[i].setZero();
    drift_stress_[i] = DriftStress();
  }
  const Real* alpha = fluid.oil_fraction.data();
  const Real rho_o = materials_.oil.density, rho_w = materials_.water.density;
  const Real tau = config_.drift_tau, sigma = config_.diffusion_sigma;
  // A particle takes part when it is mixed or a neighbour's composition differs from its own;
  // the drift of one that does is computed at once, while its neighbours are in cache.
  for_each_active(fluid, [&](Index i) {
    const Real ai = alpha[i];
    bool differs = ai > 0 && ai < 1;
    const auto& ff = nb.fluid;
    for (Index k = ff.lists.offsets[i]; k < ff.lists.offsets[i + 1] && !differs; ++k)
      differs = alpha[ff.lists.indices[k]] != ai;
    is_interface_[i] = differs ? 1 : 0;
    if (!differs) return;
    Vec3 grad_alpha = Vec3::Zero();
    Real kernel_sum = fluid.rest_volume[i] * nb.kernel_at_zero(),
         density_sum = kernel_sum * fluid.rest_density[i];
    Vec3 grad_p_oil = Vec3::Zero(), grad_p_water = Vec3::Zero();
    nb.fluid.for_each(i, [&](Index j, Index k) {
      const Vec3& g = nb.fluid.gradient[k];
      grad_alpha += (alpha[j] - ai) * g;
      const Real vw = fluid.rest_volume[j] * nb.fluid.value[k];
      kernel_sum += vw;
      density_sum += vw * fluid.rest_density[j];
      if (config_.pressure_term) {
        const Real pi = fluid.pressure[i], pj = fluid.pressure[j];
        grad_p_oil += (alpha[j] * pj - ai * pi) * g;
        grad_p_water += ((1 - alpha[j]) * pj - (1 - ai) * pi) * g;
      }
    });
    const Real rho_m = fluid.rest_density[i];
    const Real c_oil = ai * rho_o / rho_m, c_water = 1 - c_oil;
    // The slip is taken relative to the surrounding mixture, the kernel average of the rest
    // densities around i. Ren et al. take it relative to the particle's own mixture
    // (sum_k c_k rho_k), which gives a pure particle no slip at all: a pure oil particle below
    // water could then only rise by passing between water particles, which a lattice of SPH
    // particles at rest does not do. In a uniform mixture the two agree.
    const Real rho_c = density_sum / kernel_sum;
    const Vec3 a = slip_acceleration(fluid, i);
    // sum_k c_k grad alpha_k / alpha_k, finite also for a pure particle.
    const Vec3 weighted_gradient = ((rho_o - rho_w) / rho_m) * grad_alpha;
    Vec3 j_oil = (tau * ai * (rho_o - rho_c)) * a - sigma * (grad_alpha - ai * weighted_gradient);
    Vec3 j_water = (tau * (1 - ai) * (rho_w - rho_c)) * a -
                   sigma * (-grad_alpha - (1 - ai) * weighted_gradient);
    if (config_.pressure_term) {
      const Vec3 mean_grad_p = c_oil * grad_p_oil + c_water * grad_p_water;
      j_oil -= (tau * ai) * (grad_p_oil - mean_grad_p);
      j_water -= (tau * (1 - ai)) * (grad_p_water - mean_grad_p);
    }
    flux_oil_[i] = j_oil;
    // alpha_k rho_k u_k u_k = s_k s_k^T with s_k = J_k sqrt(rho_k / alpha_k).
    DriftStress stress;
    if (ai > kTinyFraction) stress.add_outer(j_oil * std::sqrt(rho_o / ai));
    if (1 - ai > kTinyFraction) stress.add_outer(j_water * std::sqrt(rho_w / (1 - ai)));
    drift_stress_[i] = stress;
  });
  interface_.clear();
  for (long i = 0; i < n; ++i)
    if (is_interface_[size_t(i)]) interface_.push_back(Index(i));
}

void MixtureModel::exchange_and_drift_momentum(FluidParticles& fluid,
                                               const ParticleNeighbourhood& nb, Real dt) {
  const Real* alpha = fluid.oil_fraction.data();
  exchange_.resize(nb.fluid.gradient.size());
  const long m = long(interface_.size());
  // In one pass over each interface particle's pairs:
  //  - the oil volume (in particle volumes) that pair (i, j) moves from i to j this step
  //    (negative: from j to i, with as much water going the other way). Upwind: each side sends
  //    oil only along its own flux (V_j grad W_ij points from i to j), so a particle without
  //    slip only receives; centred differences (J_i + J_j) would oscillate across a sharp
  //    interface and smear it. Exactly antisymmetric, as grad W_ji = -grad W_ij bit for bit;
  //  - the limiter: the share of its requested outflow each particle can afford;
  //  - the drift momentum term -div(sum_k alpha_k rho_k u_k u_k) / rho_m.
#pragma omp parallel for schedule(dynamic, 32)
  for (long li = 0; li < m; ++li) {
    const Index i = interface_[size_t(li)];
    const Real ai = alpha[i];
    const Vec3 flux_i = flux_oil_[i];
    // Oil goes from i to j only if i has oil and j water to give back, and the other way; two
    // pure particles of one phase exchange nothing. Most pairs of an interface particle are such
    // pairs, and a branch that skips them beats computing every pair as a product of 0/1 factors
    // (measured: the branch-free form made this pass 1.6 times slower).
    const Real i_has_oil = Real(ai > 0), i_has_water = Real(ai < 1);
    const bool pure_i = ai == 0 || ai == 1;
    const Real two_dt = 2 * dt;
    Real oil_out = 0, water_out = 0;
    DriftStress::Column divergence = DriftStress::Column::Zero();
    Vec3 gradient_sum = Vec3::Zero();
    const auto& ff = nb.fluid;
    for (Index k = ff.lists.offsets[i]; k < ff.lists.offsets[i + 1]; ++k) {
      const Index j = ff.lists.indices[k];
      const Vec3& g = ff.gradient[k];
      const Real aj = alpha[j];
      Real q = 0;
      if (!(pure_i && aj == ai)) {
        if (i_has_oil > 0 && aj < 1) q += std::max(flux_i.dot(g), Real(0));
        if (i_has_water > 0 && aj > 0) q -= std::max(-flux_oil_[j].dot(g), Real(0));
        q *= two_dt;
      }
      exchange_[k] = q;
      if (q > 0)
        oil_out += q;
      else
        water_out -= q;
      gradient_sum += g;
      // Zero outside the interface.
      divergence += drift_stress_[j].times(g);
    }
    // i's own share factors out of the pair sum: T_i . sum_j V_j grad W_ij.
    divergence += drift_stress_[i].times(gradient_sum);
    // The fraction change if no exchange is limited; transport() corrects the pairs that are.
    fraction_change_[i] = water_out - oil_out;
    limit_oil_[i] = oil_out > alpha[i] ? alpha[i] / oil_out : Real(1);
    limit_water_[i] = water_out > 1 - alpha[i] ? (1 - alpha[i]) / water_out : Real(1);
    fluid.acceleration[i] -= divergence.head<3>() / fluid.rest_density[i];
  }
  limited_.clear();
  for (Index i : interface_)
    if (limit_oil_[i] < 1 || limit_water_[i] < 1) limited_.push_back(i);
}

void MixtureModel::absorb_traces(FluidParticles& fluid, const ParticleNeighbourhood& nb) {
  const Real trace = config_.trace_fraction;
  if (trace <= 0) return;
  Real* alpha = fluid.oil_fraction.data();
  const auto is_oil_trace = [trace](Real a) { return a > 0 && a < trace; };
  const auto is_water_trace = [trace](Real a) { return a < 1 && a > 1 - trace; };
  // Whether j can take the trace that i holds: j is richer than i in the trace's phase (traces
  // rejoin the bulk of their phase rather than wander) and has room for it.
  const auto can_take = [](bool oil_trace, Real ai, Real aj) {
    return oil_trace ? aj > ai && aj + ai <= 1 : aj < ai && aj >= 1 - ai;
  };
  // The neighbour richest in the trace's phase that can take it, or none.
  const auto find_recipient = [&](Index i) {
    const Real ai = alpha[i];
    const bool oil_trace = is_oil_trace(ai);
    Index recipient = kNoParticle;
    if (!oil_trace && !is_water_trace(ai)) return recipient;
    Real recipient_alpha = ai;
    nb.fluid.for_each(i, [&](Index j, Index) {
      const Real aj = alpha[j];
      const bool richer = oil_trace ? aj > recipient_alpha : aj < recipient_alpha;
      if (richer && can_take(oil_trace, ai, aj)) {
        recipient = j;
        recipient_alpha = aj;
      }
    });
    return recipient;
  };
  // Searched in parallel from the fractions as they stand...
  const long m = long(interface_.size());
  chosen_recipient_.resize(interface_.size());
#pragma omp parallel for schedule(dynamic, 64)
  for (long li = 0; li < m; ++li)
    chosen_recipient_[size_t(li)] = find_recipient(interface_[size_t(li)]);
  // ...and handed over in interface order, so that the result does not depend on the thread
  // count. Where an earlier hand-over filled the chosen recipient (traces crowd around the
  // same rich particle) or changed the trace, the search is made again from the current
  // fractions, as a serial pass would have.
  for (long li = 0; li < m; ++li) {
    Index recipient = chosen_recipient_[size_t(li)];
    if (recipient == kNoParticle) continue;
    const Index i = interface_[size_t(li)];
    const Real ai = alpha[i];
    const bool oil_trace = is_oil_trace(ai);
    if (!oil_trace && !is_water_trace(ai)) continue;
    if (!can_take(oil_trace, ai, alpha[recipient])) recipient = find_recipient(i);
    if (recipient == kNoParticle) continue;
    if (oil_trace) {
      alpha[recipient] += ai;
      alpha[i] = 0;
    } else {
      alpha[recipient] -= 1 - ai;
      alpha[i] = 1;
    }
  }
}

void MixtureModel::transport(FluidParticles& fluid, const ParticleNeighbourhood& nb, Real dt) {
  // An exchange moves q min(limit of the giver, limit of the taker), so only pairs with a
  // limited particle differ from the unlimited change summed in exchange_and_drift_momentum;
  // those are a few per cent of the interface. Serial, as a correction reaches both sides of a
  // pair; a pair of two limited particles is met from both and each corrects its own side.
  const auto& ff = nb.fluid;
  for (Index i : limited_) {
    for (Index k = ff.lists.offsets[i]; k < ff.lists.offsets[i + 1]; ++k) {
      const Real q = exchange_[k];
      if (q == 0) continue;
      const Index j = ff.lists.indices[k];
      const Real share = q > 0 ? std::min(limit_oil_[i], limit_water_[j])
                               : std::min(limit_oil_[j], limit_water_[i]);
      const Real correction = q * (1 - share);
      fraction_change_[i] += correction;
      if (limit_oil_[j] == 1 && limit_water_[j] == 1) fraction_change_[j] -= correction;
    }
  }
  Real* alpha = fluid.oil_fraction.data();
  const long m = long(interface_.size());
#pragma omp parallel for schedule(static)
  for (long li = 0; li < m; ++li) {
    const Index i = interface_[size_t(li)];
    alpha[i] = std::clamp(alpha[i] + fraction_change_[i], Real(0), Real(1));
  }
  absorb_traces(fluid, nb);
  const auto update_mixture = [&](Index i) {
    fluid.set_mix(
        i, mix_phases(fluid.oil_fraction[i], materials_.water.density, materials_.water.viscosity,
                      materials_.oil.density, materials_.oil.viscosity));
  };
  // Every particle whose fraction changed is on the interface, a trace's recipient included: it
  // neighbours a mixed particle, so its composition differs from a neighbour's or is mixed.
#pragma omp parallel for schedule(static)
  for (long li = 0; li < m; ++li) update_mixture(interface_[size_t(li)]);
  // Dv/Dt of this step for the next step's slip term.
  const long n = long(fluid.active_count());
  const Real inv_dt = Real(1) / dt;
  for_each_particle(
      n,
      [&](Index i) {
        // A particle new to this slot (just emitted) has no rate yet.
        velocity_rate_[i] = step_start_id_[i] == fluid.id[i]
                                ? Vec3((fluid.velocity[i] - step_start_velocity_[i]) * inv_dt)
                                : Vec3::Zero();
        step_start_velocity_[i] = fluid.velocity[i];
        step_start_id_[i] = fluid.id[i];
      },
      Schedule::kStatic);
}

}  // namespace sph
