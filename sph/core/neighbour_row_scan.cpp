#include "sph/core/neighbour_row_scan.h"

#include <cstdint>
#include <type_traits>

// The SIMD versions test 32-bit floats (not a SPILL_DOUBLE build) on x86-64.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(SPILL_DOUBLE)
#include <immintrin.h>
#define SPILL_X86_SIMD 1
#endif

// This file is compiled with -ffp-contract=off (sph/CMakeLists.txt): a squared distance is
// dx*dx + dy*dy + dz*dz rounded after every operation in every version, never a fused
// multiply-add in one and not in another, so that all versions agree on every borderline pair.

namespace sph {

namespace {

size_t scan_scalar(const SortedPoints& p, Index begin, Index end, const Real* q, Real r2,
                   Index self, Index* out) {
  const Real qx = q[0], qy = q[1], qz = q[2];
  size_t n = 0;
  // Branch-free compaction: about one candidate in six is a neighbour, a branch on it would
  // mispredict often.
  for (Index k = begin; k < end; ++k) {
    const Real dx = p.x[k] - qx, dy = p.y[k] - qy, dz = p.z[k] - qz;
    const Index j = p.index[k];
    out[n] = j;
    n += size_t((dx * dx + dy * dy + dz * dz < r2) & (j != self));
  }
  return n;
}

#ifdef SPILL_X86_SIMD

// For each 8-bit mask, the lanes whose bit is set, first to last, then zeros: the permutation
// that packs the kept lanes of an 8-lane vector to its front.
struct PackPermutations {
  std::int32_t lanes[256][8];
};

constexpr PackPermutations make_pack_permutations() {
  PackPermutations table{};
  for (int mask = 0; mask < 256; ++mask) {
    int n = 0;
    for (int lane = 0; lane < 8; ++lane)
      if (mask & (1 << lane)) table.lanes[mask][n++] = lane;
  }
  return table;
}

constexpr PackPermutations kPack = make_pack_permutations();

__attribute__((target("avx2,popcnt"))) size_t scan_avx2(const SortedPoints& p, Index begin,
                                                        Index end, const Real* q, Real r2,
                                                        Index self, Index* out) {
  const __m256 qx = _mm256_set1_ps(q[0]), qy = _mm256_set1_ps(q[1]), qz = _mm256_set1_ps(q[2]);
  const __m256 radius2 = _mm256_set1_ps(r2);
  const __m256i self_id = _mm256_set1_epi32(std::int32_t(self));
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  size_t n = 0;
  for (Index k = begin; k < end; k += 8) {
    // The last vector reads only the lanes in range (masked loads do not touch the others).
    const __m256i in_range = _mm256_cmpgt_epi32(_mm256_set1_epi32(std::int32_t(end - k)), lane);
    __m256 x, y, z;
    __m256i ids;
    if (end - k >= 8) {
      x = _mm256_loadu_ps(p.x + k);
      y = _mm256_loadu_ps(p.y + k);
      z = _mm256_loadu_ps(p.z + k);
      ids = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p.index + k));
    } else {
      x = _mm256_maskload_ps(p.x + k, in_range);
      y = _mm256_maskload_ps(p.y + k, in_range);
      z = _mm256_maskload_ps(p.z + k, in_range);
      ids = _mm256_maskload_epi32(reinterpret_cast<const int*>(p.index + k), in_range);
    }
    const __m256 dx = _mm256_sub_ps(x, qx), dy = _mm256_sub_ps(y, qy), dz = _mm256_sub_ps(z, qz);
    const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)),
                                    _mm256_mul_ps(dz, dz));
    __m256i keep = _mm256_castps_si256(_mm256_cmp_ps(d2, radius2, _CMP_LT_OQ));
    keep = _mm256_andnot_si256(_mm256_cmpeq_epi32(ids, self_id), keep);
    keep = _mm256_and_si256(keep, in_range);
    const unsigned mask = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(keep)));
    const __m256i order = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kPack.lanes[mask]));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + n),
                        _mm256_permutevar8x32_epi32(ids, order));
    n += size_t(__builtin_popcount(mask));
  }
  return n;
}

__attribute__((target("avx512f,popcnt"))) size_t scan_avx512(const SortedPoints& p, Index begin,
                                                             Index end, const Real* q, Real r2,
                                                             Index self, Index* out) {
  const __m512 qx = _mm512_set1_ps(q[0]), qy = _mm512_set1_ps(q[1]), qz = _mm512_set1_ps(q[2]);
  const __m512 radius2 = _mm512_set1_ps(r2);
  const __m512i self_id = _mm512_set1_epi32(std::int32_t(self));
  size_t n = 0;
  for (Index k = begin; k < end; k += 16) {
    const Index left = end - k;
    const __mmask16 in_range = left >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << left) - 1);
    const __m512 x = _mm512_maskz_loadu_ps(in_range, p.x + k);
    const __m512 y = _mm512_maskz_loadu_ps(in_range, p.y + k);
    const __m512 z = _mm512_maskz_loadu_ps(in_range, p.z + k);
    const __m512i ids = _mm512_maskz_loadu_epi32(in_range, p.index + k);
    const __m512 dx = _mm512_sub_ps(x, qx), dy = _mm512_sub_ps(y, qy), dz = _mm512_sub_ps(z, qz);
    const __m512 d2 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)),
                                    _mm512_mul_ps(dz, dz));
    const __mmask16 keep = _mm512_mask_cmp_ps_mask(in_range, d2, radius2, _CMP_LT_OQ) &
                           _mm512_cmpneq_epi32_mask(ids, self_id);
    // Compressed in a register and stored whole: a compressing store to memory is microcoded
    // and slow on some CPUs.
    _mm512_storeu_si512(out + n, _mm512_maskz_compress_epi32(keep, ids));
    n += size_t(__builtin_popcount(unsigned(keep)));
  }
  return n;
}

#endif  // SPILL_X86_SIMD

}  // namespace

std::vector<RowScanVersion> available_row_scans() {
  std::vector<RowScanVersion> versions = {{"scalar", &scan_scalar}};
#ifdef SPILL_X86_SIMD
  static_assert(std::is_same_v<Real, float> && sizeof(Index) == 4);
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2")) versions.push_back({"avx2", &scan_avx2});
  if (__builtin_cpu_supports("avx512f")) versions.push_back({"avx512", &scan_avx512});
#endif
  return versions;
}

}  // namespace sph
