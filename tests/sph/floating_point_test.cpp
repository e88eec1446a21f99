// flush_subnormals_to_zero: afterwards every thread of the OpenMP team computes a product that
// would be subnormal as zero, and reads a subnormal input as zero. FlushSubnormalsScope does so
// for a scope and gives every thread its mode back.

#include "sph/core/floating_point.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <limits>
#include <vector>

#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>

namespace sph {
namespace {

TEST(FloatingPoint, SubnormalsAreFlushedInEveryThread) {
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(2);
  // Keep each thread's control register to restore it: the other tests in this process run
  // with the default mode.
  std::vector<unsigned> saved(2, 0);
#pragma omp parallel num_threads(2)
  saved[size_t(omp_get_thread_num())] = _mm_getcsr();

  // 1e-30 * 1e-10 = 1e-40 lies below float's smallest normal (1.2e-38).
  volatile float tiny_product = 1e-30f;
  volatile float subnormal = 1e-40f;
  ASSERT_GT(tiny_product * 1e-10f, 0.0f) << "the default mode keeps subnormals";
  ASSERT_LT(float(subnormal), std::numeric_limits<float>::min());

  flush_subnormals_to_zero();
  std::vector<float> product(2, -1), doubled(2, -1);
  std::vector<int> seen(2, 0);
#pragma omp parallel num_threads(2)
  {
    const size_t t = size_t(omp_get_thread_num());
    seen[t] = 1;
    product[t] = tiny_product * 1e-10f;
    doubled[t] = subnormal * 2.0f;
  }
#pragma omp parallel num_threads(2)
  _mm_setcsr(saved[size_t(omp_get_thread_num())]);
  omp_set_num_threads(threads_before);

  for (size_t t = 0; t < 2; ++t) {
    ASSERT_EQ(seen[t], 1) << "thread " << t << " did not run";
    EXPECT_EQ(product[t], 0.0f) << "thread " << t << ": a subnormal result was kept";
    EXPECT_EQ(doubled[t], 0.0f) << "thread " << t << ": a subnormal input was used";
  }
}

TEST(FloatingPoint, AScopeFlushesAndGivesEveryThreadItsModeBack) {
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(2);
  std::vector<unsigned> before(2, 0), inside(2, 0), after(2, 0);
#pragma omp parallel num_threads(2)
  before[size_t(omp_get_thread_num())] = _mm_getcsr();
  {
    const FlushSubnormalsScope flushed;
#pragma omp parallel num_threads(2)
    inside[size_t(omp_get_thread_num())] = _mm_getcsr();
  }
#pragma omp parallel num_threads(2)
  after[size_t(omp_get_thread_num())] = _mm_getcsr();
  omp_set_num_threads(threads_before);
  for (size_t t = 0; t < 2; ++t) {
    EXPECT_EQ(inside[t] & 0x8040u, 0x8040u) << "thread " << t << " was not flushed";
    EXPECT_EQ(after[t], before[t]) << "thread " << t << " kept another mode";
  }
}

}  // namespace
}  // namespace sph
#endif
