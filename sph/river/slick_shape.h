#pragma once
// The shape of an oil slick seen from above, on a river or on still water: its area (top-view
// cells one particle diameter wide that hold oil), the radius of a disc of that area, its mean
// thickness (oil volume over area) and how many separate patches it is in (cells joined by an
// edge or a corner). A particle counts as oil when its oil fraction is at least 1/2; the volume
// is the oil fraction times the rest volume of every active particle. A slick that sheds a few
// single-particle droplets counts them as patches, so the share of the oil in its largest patch
// tells one slick with droplets around it from one broken into pieces.

#include "sph/core/particle_set.h"

namespace sph {

struct SlickShape {
  double area_m2 = 0;
  double equivalent_radius_m = 0;
  double mean_thickness_m = 0;  // 0 without oil
  int patches = 0;
  double largest_patch_share = 0;  // of the oil in oil particles; 0 without oil
  double oil_volume_m3 = 0;
};

SlickShape measure_slick(const FluidParticles& fluid, Real cell);

}  // namespace sph
