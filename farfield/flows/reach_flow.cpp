#include "farfield/flows/reach_flow.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "common/config_error.h"
#include "reach/raster.h"
#include "reach/run_folder.h"

namespace farfield {

ReachFlow::ReachFlow(const ReachFlowRequest& q) : dry_depth_(q.dry_depth) {
  const reach::ReachRunFolder run(q.run_dir, q.config_file, q.pointer + "/reach_run");
  steady_ = run.steady();
  const nlohmann::json terrain = run.summary().at("config").at("terrain");
  if (q.manning >= 0) {
    manning_ = q.manning;
  } else if (!terrain.value("manning_file", std::string()).empty()) {
    throw common::ConfigError(q.config_file, q.pointer + "/manning",
                              "the reach run " + q.run_dir +
                                  " took Manning's n from a raster: give one value for the drift");
  } else {
    manning_ = terrain.value("manning", 0.035);
  }
  // The outputs from the start time on.
  const size_t first = q.start_time >= 0 ? run.output_at(q.start_time, q.pointer + "/start_time")
                                         : run.outputs() - 1;
  const double start = run.time(first);
  grid_ = run.bed().grid;
  crs_wkt_ = run.bed().crs_wkt;
  bed_ = run.bed().values;
  for (size_t k = first; k < run.outputs(); ++k) {
    reach::ReachOutput output = run.read(k);
    Frame frame;
    frame.t = output.t_s - start;
    frame.depth = std::move(output.depth);
    frame.qx = std::move(output.qx);
    frame.qy = std::move(output.qy);
    // A cell the bed closes is closed whatever its depth raster holds.
    for (size_t c = 0; c < grid_.cells(); ++c)
      if (!std::isfinite(bed_[c]))
        frame.depth[c] = frame.qx[c] = frame.qy[c] = std::numeric_limits<double>::quiet_NaN();
    frames_.push_back(std::move(frame));
  }
  known_until_ = steady_ ? std::numeric_limits<double>::infinity() : frames_.back().t;
}

// Bilinear weights found once for the three fields; a cell that is closed (NaN) gives no weight.
void ReachFlow::sample_frame(const Frame& f, double x, double y, double& h, double& qx,
                             double& qy) const {
  const reach::Grid& g = grid_;
  const double fx = (x - g.x0) / g.dx - 0.5, fy = (y - g.y0) / g.dy - 0.5;
  const int i0 = int(std::floor(fx)), j0 = int(std::floor(fy));
  const double tx = fx - i0, ty = fy - j0;
  double sh = 0, sx = 0, sy = 0, weight = 0;
  for (int dj = 0; dj < 2; ++dj)
    for (int di = 0; di < 2; ++di) {
      const int i = std::clamp(i0 + di, 0, g.nx - 1), j = std::clamp(j0 + dj, 0, g.ny - 1);
      const size_t c = g.at(i, j);
      const double w = (di ? tx : 1 - tx) * (dj ? ty : 1 - ty);
      if (!(w > 0) || !std::isfinite(f.depth[c])) continue;
      sh += w * f.depth[c];
      sx += w * f.qx[c];
      sy += w * f.qy[c];
      weight += w;
    }
  if (weight > 0) {
    h = sh / weight;
    qx = sx / weight;
    qy = sy / weight;
  } else {
    h = qx = qy = std::numeric_limits<double>::quiet_NaN();
  }
}

FlowSample ReachFlow::sample(double x, double y, double t) const {
  FlowSample s;
  const reach::Grid& g = grid_;
  if (x < g.x0 || y < g.y0 || x > g.x0 + g.nx * g.dx || y > g.y0 + g.ny * g.dy) return s;
  double h, qx, qy;
  size_t k = 0;
  while (k + 1 < frames_.size() && frames_[k + 1].t <= t) ++k;
  sample_frame(frames_[k], x, y, h, qx, qy);
  if (k + 1 < frames_.size() && t > frames_[k].t) {
    double h1, qx1, qy1;
    sample_frame(frames_[k + 1], x, y, h1, qx1, qy1);
    const double a = (t - frames_[k].t) / (frames_[k + 1].t - frames_[k].t);
    h = (1 - a) * h + a * h1;
    qx = (1 - a) * qx + a * qx1;
    qy = (1 - a) * qy + a * qy1;
  }
  if (!(h >= dry_depth_)) {
    s.where = FlowWhere::bank;
    s.depth = std::isfinite(h) ? h : 0.0;
    return s;
  }
  s.where = FlowWhere::water;
  s.depth = h;
  s.u = qx / h;
  s.v = qy / h;
  s.manning = manning_;
  return s;
}

reach::WaterState ReachFlow::water_at(double t) const {
  size_t k = 0;
  while (k + 1 < frames_.size() && frames_[k + 1].t <= t) ++k;
  return {frames_[k].depth, frames_[k].qx, frames_[k].qy};
}

}  // namespace farfield
