#pragma once
// Process set-up for LibTorch work on a CPU, done once at the start of spill-train, spill-infer
// and the benchmarks:
//  - threads: LibTorch's first operation drops OpenMP to one thread (which also throttles the
//    simulator's own loops), and OpenBLAS keeps a pool of its own that torch::set_num_threads
//    does not reach, so all three are set together;
//  - allocator: glibc's malloc hands large blocks back to the OS after every step, so the
//    gather/scatter-heavy graph code page-faults its tensors in again each step (2-4x slower);
//    taking every block from the heap and never trimming it keeps them mapped.

#include <torch/torch.h>

#include <string>

namespace gnn {

struct RuntimeSettings {
  int threads = 2;       // LibTorch intra-op and OpenMP threads
  int blas_threads = 0;  // OpenBLAS threads; 0 = the same as `threads`
};

// Inference (spill-infer) runs the model's matrix products in row chunks side by side on the
// LibTorch threads, each product on one BLAS thread: the settings for that.
inline RuntimeSettings inference_runtime(int threads) {
  return {threads, 1};
}

void configure_runtime(const RuntimeSettings& settings);

// OpenBLAS's thread count as configure_runtime set it (1 when the BLAS is not OpenBLAS: the
// reference BLAS is single-threaded). Read, never changed, by library code: the fused inference
// path runs its chunks side by side only when each matrix product stays on its caller's thread.
int blas_threads();

// The device named by a --device option ("cpu", "cuda", "cuda:1"); throws std::invalid_argument
// naming the option for a malformed name or a device this LibTorch or machine does not have.
torch::Device parse_device(const std::string& name);

// Peak resident memory of this process so far, in MiB.
double peak_memory_mib();

}  // namespace gnn
