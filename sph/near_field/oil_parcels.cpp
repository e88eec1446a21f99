#include "sph/near_field/oil_parcels.h"

#include <algorithm>
#include <cmath>

namespace sph {

void OilParcelCollector::add(const Vec3& position, Real oil_fraction, Real rest_volume) {
  const double volume = double(oil_fraction) * double(rest_volume);
  if (!(volume > 0)) return;
  total_ += volume;
  const double area = std::cbrt(double(rest_volume) * double(rest_volume));
  double x, y;
  box_.to_map(double(position.x()), double(position.y()), x, y);
  if (is_oil(oil_fraction)) {
    out_.push_back({t_, x, y, volume, area, left_});
    return;
  }
  traces_ += volume;
  traces_x_ += volume * x;
  traces_y_ += volume * y;
  traces_area_ = std::max(traces_area_, area);
}

double OilParcelCollector::finish() {
  if (traces_ > 0)
    out_.push_back({t_, traces_x_ / traces_, traces_y_ / traces_, traces_, traces_area_, left_});
  return total_;
}

}  // namespace sph
