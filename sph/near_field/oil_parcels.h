#pragma once
// The near field's oil as parcels on the map, for the far field to take over: one parcel per
// particle of oil (the one oil rule, `is_oil`), and the traces carried by water particles summed
// into one parcel per call at their oil-weighted mean position, so that every bit of oil is
// handed over, to rounding. A parcel's volume is its oil fraction times the rest volume; its
// area is the particles' cross-section, volume^(2/3) each. Positions are turned from the box's
// frame into the reach's map coordinates by the window's own transform.

#include <vector>

#include "reach/near_field_window.h"
#include "sph/core/types.h"

namespace sph {

struct NearFieldParcel {
  double t = 0;         // s of the near field's clock (its scene's time)
  double x = 0, y = 0;  // map coordinates
  double volume = 0;    // m^3 of oil
  double area = 0;      // m^2
  bool left = true;     // false: still in the box at the end
};

// Collects the oil of the particles given to it at one moment, and appends the parcels to
// `out` on finish().
class OilParcelCollector {
 public:
  OilParcelCollector(const reach::NearFieldWindow& box, double t, bool left,
                     std::vector<NearFieldParcel>& out)
      : box_(box), t_(t), left_(left), out_(out) {}

  void add(const Vec3& position, Real oil_fraction, Real rest_volume);
  // Appends the traces' parcel (if any); returns the oil volume collected (m^3).
  double finish();

 private:
  const reach::NearFieldWindow& box_;
  double t_;
  bool left_;
  std::vector<NearFieldParcel>& out_;
  double traces_ = 0, traces_x_ = 0, traces_y_ = 0, traces_area_ = 0;
  double total_ = 0;
};

}  // namespace sph
