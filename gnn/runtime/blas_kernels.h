#pragma once
// OpenBLAS picks its matrix kernels for the CPU when it is loaded. Debian's OpenBLAS 0.3.21 does
// not know the newer Xeons (family 6, model 207 on this project's machines) and falls back to its
// Prescott (SSE3) kernels, a third to a quarter of the speed the CPU's AVX-512 kernels reach.
// OPENBLAS_CORETYPE would fix it, but OpenBLAS reads it before main() runs, so users would have
// to know to set it.

#include <string>

namespace gnn {

// When OpenBLAS is the BLAS, the user has not set OPENBLAS_CORETYPE, and OpenBLAS fell back to
// Prescott on a CPU with AVX2 (or AVX-512), re-selects its kernels (SkylakeX for AVX-512,
// Haswell for AVX2) through OpenBLAS's own dynamic-architecture start-up. Anything else is left
// as it is. Call before any matrix product runs on another thread (configure_runtime does).
void select_blas_kernels();

// The kernels in use, in lower case ("skylakex", "haswell", "prescott", ...), or "not OpenBLAS".
std::string blas_kernels();

}  // namespace gnn
