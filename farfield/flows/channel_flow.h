#pragma once
// A straight rectangular channel of closed form: x runs downstream from 0 to `length`, the banks
// are at y = 0 (right, looking downstream) and y = width (left), the flow is uniform. What the
// validation tests run on, where the mean drift, the mixing and the stranding have exact answers.

#include "farfield/flows/surface_flow.h"

namespace farfield {

struct ChannelFlow final : SurfaceFlow {
  double length = 1e5, width = 100;  // m
  double depth = 2;                  // m
  double speed = 1;                  // m/s along +x
  double manning = 0.03;             // s/m^(1/3)
  double cell = 10;                  // m: the resolution the drift sub-steps on (a reach's)

  double resolution() const override { return cell; }

  FlowSample sample(double x, double y, double) const override {
    FlowSample s;
    if (x < 0 || x > length) return s;  // outside
    if (y <= 0 || y >= width) {
      s.where = FlowWhere::bank;
      return s;
    }
    s.where = FlowWhere::water;
    s.depth = depth;
    s.u = speed;
    s.manning = manning;
    return s;
  }
};

}  // namespace farfield
