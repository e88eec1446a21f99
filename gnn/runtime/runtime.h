#pragma once
// Process set-up for LibTorch work on a CPU, done once at the start of spill-train, spill-infer
// and the benchmarks:
//  - threads: LibTorch's first operation drops OpenMP to one thread (which also throttles the
//    simulator's own loops), and OpenBLAS keeps a pool of its own that torch::set_num_threads
//    does not reach, so all three are set together;
//  - allocator: glibc's malloc hands large blocks back to the OS after every step, so the
//    gather/scatter-heavy graph code page-faults its tensors in again each step (2-4x slower);
//    taking every block from the heap and never trimming it keeps them mapped;
//  - matrix kernels: OpenBLAS's fallback to SSE3 kernels on CPUs it does not know is undone
//    (blas_kernels.h).

#include "gnn/runtime/blas_kernels.h"

#include <torch/torch.h>

#include <string>

namespace gnn {

struct RuntimeSettings {
  int threads = 2;       // LibTorch intra-op and OpenMP threads
  int blas_threads = 0;  // OpenBLAS threads; 0 = the same as `threads`
};

// Inference's thread mix on `threads` cores (spill-infer), by measurement (spill-infer eval on
// river_small, 8 frames, wall seconds per frame, 2 cores, runs alternating):
//  - a model whose inference runs its products in row chunks side by side (GNS-10-128) wants
//    the chunks on the LibTorch threads and BLAS on one: 2 + 1 threads 0.57 / 0.60 s, 1 + 2
//    0.89 / 0.94 s, 2 + 2 3.05 s (the chunks' threads and BLAS's fight over the cores);
//    DPI-Nets' fused inference likewise (inference_bench, river_small baseline, 16 frames, ms
//    per frame): 2 + 1 threads 16.7 / 17.4, 1 + 2 25.4 / 24.4, 2 + 2 23.9 / 24.2;
//  - PAGATNet (whole-tensor products of 64-wide latents through autograd-free LibTorch ops)
//    too: teacher 6 x 64 255 ms per frame with 2 + 1 threads, 546 ms with 2 + 2; student
//    3 x 32 57 against 116 ms;
//  - a model run as whole-tensor products, one op after another (DPI-Nets 200/300 before its
//    fused path), gets every core in both pools: 2 + 2 threads 0.36 / 0.45 / 0.47 s, 1 + 2
//    0.47 / 0.50 / 0.45 s, 2 + 1 0.44 / 0.48 / 0.48 s.
inline RuntimeSettings inference_runtime(int threads, bool infers_on_one_blas_thread = true) {
  if (infers_on_one_blas_thread) return {threads, 1};
  return {threads, threads};
}

// Training's thread mix on `threads` cores, by measurement (river_small, GNS-10-128, 3,421
// nodes and 59,990 edges per graph, 2 cores; steps per second, one run alternating):
//  - a model that trains in row chunks (GNS's hand-written processor backward) is fastest with
//    the chunks side by side on the LibTorch threads and BLAS on one: 2 + 1 threads 0.42, 1 + 2
//    0.27 (serial chunks, each product on 2 BLAS threads);
//  - a model trained through LibTorch's autograd (whole-tensor products, DPI-Nets) is fastest
//    with one LibTorch thread and the BLAS threads on every core: 1 + 2 threads 0.400, 2 + 2
//    0.307, 2 + 1 0.325 (GNS through autograd, the figures of the training-speed issue).
inline RuntimeSettings training_runtime(int threads, bool trains_in_chunks) {
  if (trains_in_chunks) return {threads, 1};
  return {1, threads};
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
