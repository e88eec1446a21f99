#pragma once
// The per-particle loops of the solvers and forces, in parallel over OpenMP threads: one place
// for the loop preamble (OpenMP wants a signed index; particles are numbered by Index) and for
// the choice of schedule. Neighbour loops differ in cost from particle to particle (a free
// surface has half the neighbours of the bulk), so they take dynamic chunks of 64; updates of
// equal cost per particle are split statically, which also fixes a reduction's order for a
// given thread count.

#include <algorithm>

#include "sph/core/particle_set.h"
#include "sph/core/types.h"

namespace sph {

enum class Schedule { kDynamic, kStatic };

// Calls f(i) for every i in [0, n).
template <class F>
void for_each_particle(Index n, F&& f, Schedule schedule = Schedule::kDynamic) {
  if (schedule == Schedule::kStatic) {
#pragma omp parallel for schedule(static)
    for (long i = 0; i < long(n); ++i) f(Index(i));
  } else {
#pragma omp parallel for schedule(dynamic, 64)
    for (long i = 0; i < long(n); ++i) f(Index(i));
  }
}

// Calls f(i) for every active fluid particle i.
template <class F>
void for_each_active(const FluidParticles& fluid, F&& f, Schedule schedule = Schedule::kDynamic) {
  for_each_particle(fluid.active_count(), f, schedule);
}

// The sum (in double) and the largest of a per-particle figure, e.g. a solver's density error:
// f(i) returns {what particle i adds to the sum, what it offers to the largest}.
struct SumAndLargest {
  double sum = 0;
  Real largest = 0;
};
struct Contribution {
  Real to_sum = 0;
  Real to_largest = 0;
};
template <class F>
SumAndLargest sum_and_largest(Index n, F&& f, Schedule schedule = Schedule::kDynamic) {
  double sum = 0;
  Real largest = 0;
  if (schedule == Schedule::kStatic) {
#pragma omp parallel for schedule(static) reduction(+ : sum) reduction(max : largest)
    for (long i = 0; i < long(n); ++i) {
      const Contribution c = f(Index(i));
      sum += double(c.to_sum);
      largest = std::max(largest, c.to_largest);
    }
  } else {
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : sum) reduction(max : largest)
    for (long i = 0; i < long(n); ++i) {
      const Contribution c = f(Index(i));
      sum += double(c.to_sum);
      largest = std::max(largest, c.to_largest);
    }
  }
  return {sum, largest};
}

}  // namespace sph
