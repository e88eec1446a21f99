#pragma once
// The flow of a finished reach run (`spill-sim reach`, reach/reach_run.h) as the far field's
// surface flow: depth and discharge per width bilinear between the cells' centres of its output
// rasters, the velocity their ratio (so a dry cell beside a wet one does not drag the speed to
// 0), linear in time between output times. A run that reached a steady state holds its last
// output for ever after; any other run refuses times past its end.

#include <string>
#include <vector>

#include "farfield/flows/surface_flow.h"
#include "reach/grid.h"
#include "reach/shallow_water.h"

namespace farfield {

struct ReachFlowRequest {
  std::string run_dir;
  double start_time = -1;   // the reach run's time (s) at forecast time 0; < 0: its last output
  double manning = -1;      // s/m^(1/3); < 0: the reach config's constant
  double dry_depth = 0.01;  // m: shallower water is shore
  // For error messages: the config file and the JSON pointer of these settings.
  std::string config_file, pointer;
};

class ReachFlow final : public SurfaceFlow {
 public:
  // Throws common::ConfigError naming the config file and key: not a reach run, no outputs, a
  // start time with no output, a run with a Manning raster and no `manning` given.
  explicit ReachFlow(const ReachFlowRequest& request);

  FlowSample sample(double x, double y, double t) const override;
  double resolution() const override { return std::min(grid_.dx, grid_.dy); }
  std::string crs_wkt() const override { return crs_wkt_; }

  const reach::Grid& grid() const { return grid_; }
  // The forecast time (s) up to which the flow is known; infinity for a steady run.
  double known_until() const { return known_until_; }
  bool steady() const { return steady_; }
  // The run's bed (NaN where closed), for maps.
  const reach::Field& bed() const { return bed_; }
  // The output in force at forecast time t as the reach's water state (for maps).
  reach::WaterState water_at(double t) const;

 private:
  struct Frame {
    double t = 0;  // forecast time
    reach::Field depth, qx, qy;
  };
  void sample_frame(const Frame& f, double x, double y, double& h, double& qx, double& qy) const;

  reach::Grid grid_;
  std::string crs_wkt_;
  reach::Field bed_;
  std::vector<Frame> frames_;
  double manning_ = 0.035, dry_depth_ = 0.01;
  bool steady_ = false;
  double known_until_ = 0;
};

}  // namespace farfield
