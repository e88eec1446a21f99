#pragma once
// Static boundary particles (walls, vessel, terrain) with the volumes of
//   Akinci, Ihmsen, Akinci, Solenthaler, Teschner, "Versatile rigid-fluid coupling for
//   incompressible SPH", ACM TOG 31(4), 2012, eq. 4:  V_b = 1 / sum_k W(x_b - x_k)
// over the boundary neighbours k (b included), which corrects for uneven sampling. A single layer
// at one particle diameter spacing is enough: the fluid sees the wall through the kernel sum and
// the pressure is mirrored onto it (p_b = p_i) by the solvers.

#include <vector>

#include "sph/boundary/boundary_configs.h"
#include "sph/core/kernels.h"
#include "sph/core/types.h"

namespace sph {

struct BoundaryParticles {
  std::vector<Vec3> position;
  std::vector<Real> volume;  // m^3, Akinci et al. 2012

  Index size() const { return static_cast<Index>(position.size()); }
};

// Points on the faces of a box, spaced at most `spacing` apart (each edge is divided evenly, so
// corners and edges are sampled exactly once). `open_top` leaves out the face z = max.
std::vector<Vec3> sample_box_surface(const Vec3& lo, const Vec3& hi, Real spacing, bool open_top);

// Points on the surface z = h(x, y) of a height field (bilinear between grid nodes), spaced at most
// `spacing` apart horizontally, with vertical columns filling steps steeper than one spacing so
// that fluid cannot slip through a steep bank.
std::vector<Vec3> sample_height_field(const HeightFieldConfig& field, Real spacing);

// Akinci volumes for the given positions, with the kernel of the scene.
std::vector<Real> boundary_volumes(const std::vector<Vec3>& positions, KernelKind kernel,
                                   Real support_radius);

// All boundary particles of a scene's surfaces (boxes, then height fields, a terrain among them),
// sampled `spacing` (the particle diameter) apart, with volumes. The layer is placed behind each
// declared surface (outside a tank's walls, inside an obstacle, below a terrain), so the declared
// surfaces are where the fluid ends.
BoundaryParticles build_boundary(const std::vector<BoxConfig>& boxes,
                                 const std::vector<HeightFieldConfig>& height_fields, Real spacing,
                                 Real support_radius, KernelKind kernel);

}  // namespace sph
