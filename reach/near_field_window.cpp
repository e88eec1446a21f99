#include "reach/near_field_window.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/config_error.h"
#include "reach/grid_sampling.h"
#include "reach/raster.h"
#include "reach/run_folder.h"

namespace reach {

namespace {

constexpr double kPi = 3.14159265358979323846;
const double kNan = std::numeric_limits<double>::quiet_NaN();

std::string point_text(double east, double north) {
  std::ostringstream s;
  s.precision(10);
  s << "(" << east << ", " << north << ")";
  return s.str();
}

}  // namespace

void NearFieldWindow::to_map(double x, double y, double& east, double& north) const {
  const double a = heading_deg * kPi / 180;
  const double ex = std::sin(a), ey = std::cos(a);  // +x of the box, in (east, north)
  const double u = x - 0.5 * length;
  east = centre_x + u * ex - y * ey;
  north = centre_y + u * ey + y * ex;
}

double NearFieldWindow::section_level(double x, double min_depth) const {
  const int i = std::clamp(int(std::lround(x / cell_size)), 0, nx - 1);
  double sum = 0;
  int n = 0;
  for (int j = 0; j < ny; ++j)
    if (depth[at(i, j)] > min_depth) {
      sum += bed[at(i, j)] + depth[at(i, j)];
      ++n;
    }
  return n ? sum / n : kNan;
}

double NearFieldWindow::section_velocity(double x, double min_depth) const {
  const int i = std::clamp(int(std::lround(x / cell_size)), 0, nx - 1);
  double discharge = 0, area = 0;
  for (int j = 0; j < ny; ++j)
    if (depth[at(i, j)] > min_depth) {
      discharge += depth[at(i, j)] * along[at(i, j)];
      area += depth[at(i, j)];
    }
  return area > 0 ? discharge / area : kNan;
}

NearFieldWindow sample_near_field(const NearFieldRequest& q) {
  const auto refuse = [&](const std::string& key, const std::string& message) {
    return common::ConfigError(q.config_file, q.pointer + key, message);
  };
  const ReachRunFolder run(q.run_dir, q.config_file, q.pointer + "/run");
  const ReachOutput output =
      run.read(q.time >= 0 ? run.output_at(q.time, q.pointer + "/time") : run.outputs() - 1);
  const Raster& bed = run.bed();
  const Grid& g = bed.grid;
  const Field &depth = output.depth, &qx = output.qx, &qy = output.qy;

  NearFieldWindow w;
  w.cell_size = q.cell_size;
  w.width = q.width;
  w.length = q.length;
  w.centre_x = q.centre_x;
  w.centre_y = q.centre_y;
  w.crs_wkt = bed.crs_wkt;
  w.time_s = output.t_s;
  w.heading_deg = q.heading_deg;
  if (w.heading_deg < 0) {
    // The mean flow over a square of the box's smaller side around its centre.
    const double half = 0.5 * std::min(q.length, q.width);
    double sx = 0, sy = 0, sh = 0;
    for (int b = 0; b <= 20; ++b)
      for (int a = 0; a <= 20; ++a) {
        const double x = q.centre_x - half + a * half / 10, y = q.centre_y - half + b * half / 10;
        const double h = bilinear_valid(depth, g, x, y);
        if (!(h > q.min_depth)) continue;
        sx += bilinear_valid(qx, g, x, y);
        sy += bilinear_valid(qy, g, x, y);
        sh += h;
      }
    if (!(sh > 0) || std::hypot(sx, sy) < 1e-3 * sh)
      throw refuse("/heading", "the reach has no flow around " +
                                   point_text(q.centre_x, q.centre_y) +
                                   " to take the box's direction from: give the heading");
    w.heading_deg = std::fmod(std::atan2(sx, sy) * 180 / kPi + 360, 360);
  }
  // Every corner inside the reach's grid.
  const double x1 = g.x0 + g.nx * g.dx, y1 = g.y0 + g.ny * g.dy;
  for (const double cx : {0.0, q.length})
    for (const double cy : {-0.5 * q.width, 0.5 * q.width}) {
      double e = 0, n = 0;
      w.to_map(cx, cy, e, n);
      if (e < g.x0 || e > x1 || n < g.y0 || n > y1)
        throw refuse("/centre", "the box's corner " + point_text(e, n) +
                                    " lies outside the reach's grid (" + point_text(g.x0, g.y0) +
                                    " to " + point_text(x1, y1) + ", " + q.run_dir + "/bed.tif)");
    }

  w.nx = int(std::floor(q.length / q.cell_size + 1e-9)) + 1;
  w.ny = int(std::floor(q.width / q.cell_size + 1e-9)) + 1;
  const size_t points = size_t(w.nx) * size_t(w.ny);
  w.bed.resize(points);
  w.depth.resize(points);
  w.along.resize(points);
  w.across.resize(points);
  const double a = w.heading_deg * kPi / 180;
  const double ex = std::sin(a), ey = std::cos(a);
  bool wet = false;
  for (int j = 0; j < w.ny; ++j)
    for (int i = 0; i < w.nx; ++i) {
      double e = 0, n = 0;
      w.to_map(w.x(i), w.y(j), e, n);
      const size_t k = w.at(i, j);
      w.bed[k] = bilinear_valid(bed.values, g, e, n);
      if (!std::isfinite(w.bed[k]))
        throw refuse("/centre", "the box reaches closed or nodata cells of the reach at " +
                                    point_text(e, n) + " (" + q.run_dir + "/bed.tif)");
      const double h = bilinear_valid(depth, g, e, n);
      w.depth[k] = std::isfinite(h) ? std::max(h, 0.0) : 0.0;
      if (w.depth[k] > q.min_depth) {
        wet = true;
        const double fx = bilinear_valid(qx, g, e, n), fy = bilinear_valid(qy, g, e, n);
        w.along[k] = (fx * ex + fy * ey) / w.depth[k];
        w.across[k] = (-fx * ey + fy * ex) / w.depth[k];
      }
    }
  if (!wet)
    throw refuse("/centre", "the box around " + point_text(q.centre_x, q.centre_y) +
                                " holds no water deeper than " + std::to_string(q.min_depth) +
                                " m at " + std::to_string(std::lround(w.time_s)) + " s");
  return w;
}

}  // namespace reach
