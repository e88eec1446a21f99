#pragma once
// The memory this process may use, for refusing work that would not fit before allocating it
// (the SPH scene's particles, the reach's raster, the forecast's elements).

namespace common {

// Bytes: the machine's physical memory, or less under a resource limit (ulimit -v or -d, as the
// input fuzzers run it); 1e15 (no bound) when the machine does not say.
double physical_memory_bytes();

}  // namespace common
