#pragma once
// Floating-point mode of the simulating threads.

#include <vector>

namespace sph {

// Makes every thread of the current OpenMP team (call it after omp_set_num_threads) and the
// calling thread treat subnormal floats (below 1.2e-38 in float) as zero, in inputs and
// results. Settling fluid and the mixture model's drift terms (squares of fluxes near zero) make
// such values, and each operation on one costs a microcode assist of about a hundred cycles:
// measured on the two-phase dam break, MTDF-SPH's pressure solve took 13 % longer than DFSPH's
// at the same iteration counts until they were flushed. Nothing physical lives at 1e-38.
// A no-op where the CPU has no such mode (non-x86 builds).
void flush_subnormals_to_zero();

// flush_subnormals_to_zero for a scope: the calling thread and the OpenMP team get back the mode
// they had when it ends. For a simulation inside a process that goes on with other work
// (spill-train simulating its data, then training, which must compute as it does on read data).
class FlushSubnormalsScope {
 public:
  FlushSubnormalsScope();
  ~FlushSubnormalsScope();
  FlushSubnormalsScope(const FlushSubnormalsScope&) = delete;
  FlushSubnormalsScope& operator=(const FlushSubnormalsScope&) = delete;

 private:
  std::vector<unsigned> saved_;  // the mode of team thread k (k = 0: the calling thread)
};

}  // namespace sph
