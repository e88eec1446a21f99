#pragma once
// The river under the slick: depth, depth-averaged velocity and roughness wherever an element
// is. The far field needs nothing else of the flow, so a straight channel of closed form (tests)
// and a finished reach run (forecasts) are both behind this one interface.

#include <string>

namespace farfield {

enum class FlowWhere {
  water,   // open water
  bank,    // a dry or closed cell inside the flow's domain: the shore
  outside  // beyond the domain's edge
};

struct FlowSample {
  FlowWhere where = FlowWhere::outside;
  double depth = 0;     // m
  double u = 0, v = 0;  // m/s, depth-averaged, east and north
  double manning = 0;   // s/m^(1/3)
};

class SurfaceFlow {
 public:
  virtual ~SurfaceFlow() = default;
  // The flow at map point (x, y) at forecast time t (s). Thread-safe.
  virtual FlowSample sample(double x, double y, double t) const = 0;
  // The size of the flow's cells (m): the sub-steps of the drift and the differences of the
  // mixing coefficients are taken on it.
  virtual double resolution() const = 0;
  // The CRS of the map coordinates as WKT (empty for a local frame).
  virtual std::string crs_wkt() const { return {}; }
};

}  // namespace farfield
