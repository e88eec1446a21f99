#pragma once
// The innermost loop of the neighbour search: the candidates of one contiguous range of the
// grid's sorted points are tested against a query and those within the radius are packed into
// an output list. It is a quarter of a DFSPH step, so it has SIMD versions (8 and 16 floats per
// test, packed by a permutation or a compress) chosen once by what the CPU offers at run time;
// the build itself stays portable (x86-64 baseline). Every version computes each squared
// distance with the same operations in the same order as the scalar one, so all of them return
// the same lists, bit for bit.

#include <cstddef>
#include <string>
#include <vector>

#include "sph/core/types.h"

namespace sph {

// The grid's sorted points as coordinate arrays.
struct SortedPoints {
  const Real* x;
  const Real* y;
  const Real* z;
  const Index* index;  // the caller's index of each sorted point
};

// How many entries past its result a scan may write (a SIMD version stores whole vectors).
constexpr size_t kRowScanSlack = 16;

// One query q against the sorted points [begin, end): writes the caller's indices j of the
// points with |p - q|^2 < r2 and j != self, in sorted order, to out and returns how many. out
// must have room for (end - begin) + kRowScanSlack entries.
using RowScan = size_t (*)(const SortedPoints& points, Index begin, Index end, const Real* q,
                           Real r2, Index self, Index* out);

struct RowScanVersion {
  std::string name;  // "scalar", "avx2", "avx512"
  RowScan scan;
};

// Every version this build and CPU can run, the scalar one first, the fastest last.
std::vector<RowScanVersion> available_row_scans();

}  // namespace sph
