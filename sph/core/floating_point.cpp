#include "sph/core/floating_point.h"

#include <omp.h>

#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#define SPILL_HAS_MXCSR 1
#endif

namespace sph {

namespace {

// Flush-to-zero (bit 15) for results and denormals-are-zero (bit 6) for inputs.
constexpr unsigned kFlushBits = 0x8040u;

unsigned mode_of_this_thread() {
#ifdef SPILL_HAS_MXCSR
  return _mm_getcsr();
#else
  return 0;
#endif
}

void set_flush_bits_of_this_thread(unsigned bits) {
#ifdef SPILL_HAS_MXCSR
  _mm_setcsr((_mm_getcsr() & ~kFlushBits) | (bits & kFlushBits));
#else
  (void)bits;
#endif
}

void flush_in_this_thread() {
  set_flush_bits_of_this_thread(kFlushBits);
}

}  // namespace

void flush_subnormals_to_zero() {
  flush_in_this_thread();
  // The control register is per thread: set it in each worker of the team the loops will use.
#pragma omp parallel
  flush_in_this_thread();
}

FlushSubnormalsScope::FlushSubnormalsScope() {
  saved_.assign(size_t(omp_get_max_threads()), mode_of_this_thread());
  const int team = int(saved_.size());
#pragma omp parallel num_threads(team)
  saved_[size_t(omp_get_thread_num())] = mode_of_this_thread();
  flush_subnormals_to_zero();
}

FlushSubnormalsScope::~FlushSubnormalsScope() {
  const int team = int(saved_.size());
#pragma omp parallel num_threads(team)
  set_flush_bits_of_this_thread(saved_[size_t(omp_get_thread_num())]);
  set_flush_bits_of_this_thread(saved_[0]);
}

}  // namespace sph
