#include "sim/commands/command.h"

#include <omp.h>

#include "sph/core/floating_point.h"

namespace sim {

int use_threads(int requested) {
  const int n = requested > 0 ? requested : omp_get_num_procs();
  omp_set_num_threads(n);
  sph::flush_subnormals_to_zero();
  return n;
}

}  // namespace sim
