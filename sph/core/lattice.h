#pragma once
// The cubic particle lattice that fluid blocks are filled with, and the kernel sums over it that
// fix the rest volume of fluid particles and the placement of the boundary layer.

#include <vector>

#include "sph/core/kernels.h"
#include "sph/core/types.h"

namespace sph {

// Points filling [lo, hi] on a cubic lattice with spacing `spacing` whose first point sits half a
// spacing inside the lower corner (so a block touching a wall has its centres one radius off it).
std::vector<Vec3> lattice_points(const Vec3& lo, const Vec3& hi, Real spacing);

// Rest volume that gives an interior particle of the lattice exactly the rest density
// (1 / sum_j W_ij over the lattice), so a block starts at rho = rho0 instead of a few percent off.
Real lattice_rest_volume(KernelKind kernel, Real support_radius, Real spacing);

// How far behind a flat wall surface a single boundary layer (Akinci volumes, same spacing) must
// sit so that a fluid lattice resting against the surface (first centres half a spacing in front
// of it) has exactly the rest density in its first layer. Found by bisection on the kernel sums.
Real boundary_layer_offset(KernelKind kernel, Real support_radius, Real spacing);

}  // namespace sph
