#pragma once
// A flow whose velocities are another's times a factor: an ensemble member's uncertain current
// (GNOME's uncertainty spills scale the currents likewise). Depth and roughness are the flow's,
// so the bed's shear velocity, and with it the mixing, scale with the current.

#include <memory>
#include <string>

#include "farfield/flows/surface_flow.h"

namespace farfield {

class ScaledFlow : public SurfaceFlow {
 public:
  ScaledFlow(std::shared_ptr<const SurfaceFlow> flow, double velocity_scale)
      : flow_(std::move(flow)), scale_(velocity_scale) {}
  FlowSample sample(double x, double y, double t) const override {
    FlowSample s = flow_->sample(x, y, t);
    s.u *= scale_;
    s.v *= scale_;
    return s;
  }
  double resolution() const override { return flow_->resolution(); }
  std::string crs_wkt() const override { return flow_->crs_wkt(); }

 private:
  std::shared_ptr<const SurfaceFlow> flow_;
  double scale_;
};

}  // namespace farfield
