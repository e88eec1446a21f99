#include "gnn/runtime/blas_kernels.h"

#include <dlfcn.h>
#include <cctype>
#include <cstdlib>

namespace gnn {

namespace {

using CoreName = char* (*)();
using DynamicStep = void (*)();

// The kernel family this CPU can run that OpenBLAS 0.3.21 has, or nullptr when Prescott's is
// already the best it has. SkylakeX's kernels need the AVX-512 foundation, BW, DQ and VL sets.
const char* best_supported_core() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl"))
    return "SkylakeX";
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return "Haswell";
  return nullptr;
}

}  // namespace

std::string blas_kernels() {
  auto core_name = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  if (!core_name) return "not OpenBLAS";
  const char* name = core_name();
  std::string lower = name ? name : "unknown";
  for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

void select_blas_kernels() {
  // Looked up at run time, as the thread setters are: the BLAS behind LibTorch is chosen by
  // Debian's alternatives, and a single-architecture OpenBLAS has no dynamic start-up.
  auto quit = reinterpret_cast<DynamicStep>(dlsym(RTLD_DEFAULT, "gotoblas_dynamic_quit"));
  auto init = reinterpret_cast<DynamicStep>(dlsym(RTLD_DEFAULT, "gotoblas_dynamic_init"));
  if (!quit || !init) return;
  if (std::getenv("OPENBLAS_CORETYPE")) return;  // the user's choice stands
  if (blas_kernels() != "prescott") return;
  const char* better = best_supported_core();
  if (!better) return;
  // OpenBLAS's start-up reads the variable; it is removed again so that nothing this process
  // starts inherits a choice the user did not make.
  setenv("OPENBLAS_CORETYPE", better, 1);
  quit();
  init();
  unsetenv("OPENBLAS_CORETYPE");
}

}  // namespace gnn
