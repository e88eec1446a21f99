#include "gnn/runtime/runtime.h"

#include "common/exit_codes.h"
#include "gnn/runtime/blas_kernels.h"

#include <dlfcn.h>
#include <malloc.h>
#include <omp.h>
#include <sys/resource.h>
#include <torch/torch.h>
#include <limits>

namespace gnn {

void configure_runtime(const RuntimeSettings& settings) {
  // Every block from the heap, never from mmap (glibc caps M_MMAP_THRESHOLD at 32 MiB, smaller
  // than one edge tensor), and freed memory kept for the next step instead of trimmed: otherwise
  // each step page-faults and zeroes its tensors afresh (measured: 7 % of a forward in the
  // kernel's clear_page).
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
  mallopt(M_TOP_PAD, 64 << 20);
  select_blas_kernels();
  const int threads = settings.threads > 0 ? settings.threads : 1;
  torch::set_num_threads(threads);
  omp_set_num_threads(threads);
  // Looked up at run time: the BLAS behind LibTorch is chosen by Debian's alternatives and may
  // not be OpenBLAS at all. Set here once; library code only reads it (blas_threads()).
  using SetThreads = void (*)(int);
  if (auto set_blas = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
    set_blas(settings.blas_threads > 0 ? settings.blas_threads : threads);
}

int blas_threads() {
  using GetThreads = int (*)();
  auto get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  return get ? get() : 1;
}

double peak_memory_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

torch::Device parse_device(const std::string& name) {
  try {
    const torch::Device device(name);
    if (device.is_cuda() && !torch::cuda::is_available())
      throw common::InputError("--device " + name +
                               ": no CUDA device is available to this LibTorch build");
    if (!device.is_cpu() && !device.is_cuda())
      throw common::InputError("--device " + name + ": expected cpu or cuda[:N]");
    return device;
  } catch (const c10::Error&) {
    throw common::InputError("--device " + name + ": expected cpu or cuda[:N]");
  }
}

}  // namespace gnn
