#pragma once
// A geometric reference for the surface typing of heterogeneous_typing.h, independent of any
// kernel: a fluid particle is at the free surface when no fluid particle (of either phase) lies in
// the upward cone above it, of half-angle `half_angle` around the vertical and within `reach`.
// Particles on a lattice below a flat surface have their upper neighbour straight above them;
// the top layer has none. It is what the kernel-sum threshold gamma is calibrated against
// (tests/bench/surface_typing_study.cpp, docs/results/surface_typing.md).

#include <torch/torch.h>

#include "gnn/graph/heterogeneous_typing.h"

namespace gnn {

// `fluid` [F, 3] float32 positions (z up); returns [F] bool, true at the free surface.
torch::Tensor free_surface_by_cone(const torch::Tensor& fluid, double reach, double half_angle);

// One frame's fluid nodes as the typing sees them at `radius` (boundary included, phases by the
// oil fraction), beside the cone reference of half-angle `half_angle` and reach `reach`.
struct FrameSurfaceTyping {
  torch::Tensor kernel_sum, centroid_offset;  // [F] float32, HeterogeneousTyping's
  torch::Tensor reference;                    // [F] bool, free_surface_by_cone
  torch::Tensor outside_band;  // [F] bool: not in the interface band, so typed by the rule
};

// `fluid` [F, 3], `oil_fraction` [F], `boundary` [M, 3]; `diameter` the particle diameter.
FrameSurfaceTyping type_frame_surface(const torch::Tensor& fluid, const torch::Tensor& oil_fraction,
                                      const torch::Tensor& boundary, double radius, double diameter,
                                      double reach, double half_angle);

// The nodes `rule` types surface from their kernel sums and centroid offsets (the interface band
// aside).
torch::Tensor surface_by_rule(const SurfaceRule& rule, const FrameSurfaceTyping& frame);

// How a surface typing agrees with a reference, over the nodes where `counted` is true.
struct SurfaceAgreement {
  int64_t nodes = 0;
  double typed_share = 0;      // share of the nodes typed surface
  double reference_share = 0;  // share at the surface by the reference
  double precision = 0;        // of the nodes typed surface, the share the reference agrees on
  double recall = 0;           // of the reference's surface nodes, the share typed surface
  double f1 = 0;               // harmonic mean of precision and recall
};

SurfaceAgreement surface_agreement(const torch::Tensor& typed, const torch::Tensor& reference,
                                   const torch::Tensor& counted);

}  // namespace gnn
