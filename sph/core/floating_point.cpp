#include "sph/core/floating_point.h"

#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#define SPILL_HAS_MXCSR 1
#endif

namespace sph {

namespace {

void flush_in_this_thread() {
#ifdef SPILL_HAS_MXCSR
  // Flush-to-zero (bit 15) for results and denormals-are-zero (bit 6) for inputs.
  _mm_setcsr(_mm_getcsr() | 0x8040u);
#endif
}

}  // namespace

void flush_subnormals_to_zero() {
  flush_in_this_thread();
  // The control register is per thread: set it in each worker of the team the loops will use.
#pragma omp parallel
  flush_in_this_thread();
}

}  // namespace sph
