#include "reach/near_field_window.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/config_error.h"
#include "common/json_file.h"
#include "reach/grid_sampling.h"
#include "reach/raster.h"

namespace reach {

namespace fs = std::filesystem;

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
  const fs::path dir(q.run_dir);
  if (!fs::is_regular_file(dir / "reach.json"))
    throw refuse("/run", q.run_dir + " is not a reach run folder (no reach.json)");
  if (!fs::is_regular_file(dir / "bed.tif"))
    throw refuse("/run", q.run_dir +
                             " has no bed.tif (written by spill-sim reach since the near field "
                             "could take its terrain from it): run the reach again");
  const nlohmann::json summary = common::load_json_file((dir / "reach.json").string(), "reach run");
  const nlohmann::json& frames = summary.at("frames");
  if (frames.empty()) throw refuse("/run", q.run_dir + "/reach.json lists no output");
  const nlohmann::json* frame = &frames.back();
  if (q.time >= 0) {
    std::string times;
    frame = nullptr;
    for (const auto& f : frames) {
      const double t = f.at("t_s").get<double>();
      times += (times.empty() ? "" : ", ") + std::to_string(std::lround(t));
      // The output nearest the time asked, within half a second (frames may be closer).
      if (std::abs(t - q.time) <= 0.5 &&
          (!frame || std::abs(t - q.time) < std::abs((*frame).at("t_s").get<double>() - q.time)))
        frame = &f;
    }
    if (!frame)
      throw refuse("/time", "the reach run has no output at " + std::to_string(q.time) +
                                " s (its outputs: " + times + " s)");
  }
  // Velocities are nodata where dry (a frame of a dry start has none at all); the box's own
  // check refuses a box with no water.
  const auto raster = [&](const char* what) {
    return read_raster((dir / (*frame).at("files").at(what).get<std::string>()).string(),
                       {{}, 1, true});
  };
  const Raster bed = read_raster((dir / "bed.tif").string());
  const Raster depth = raster("depth"), vx = raster("velocity_x"), vy = raster("velocity_y");
  const Grid& g = bed.grid;
  // Discharge per width, zero where dry and NaN where closed, so that it interpolates smoothly
  // up to a shore.
  Field qx(g.cells()), qy(g.cells());
  for (size_t c = 0; c < g.cells(); ++c) {
    const double h = depth.values[c];
    qx[c] = !std::isfinite(h) ? kNan : std::isfinite(vx.values[c]) ? h * vx.values[c] : 0.0;
    qy[c] = !std::isfinite(h) ? kNan : std::isfinite(vy.values[c]) ? h * vy.values[c] : 0.0;
  }

  NearFieldWindow w;
  w.cell_size = q.cell_size;
  w.width = q.width;
  w.length = q.length;
  w.centre_x = q.centre_x;
  w.centre_y = q.centre_y;
  w.crs_wkt = bed.crs_wkt;
  w.time_s = (*frame).at("t_s").get<double>();
  w.heading_deg = q.heading_deg;
  if (w.heading_deg < 0) {
    // The mean flow over a square of the box's smaller side around its centre.
    const double half = 0.5 * std::min(q.length, q.width);
    double sx = 0, sy = 0, sh = 0;
    for (int b = 0; b <= 20; ++b)
      for (int a = 0; a <= 20; ++a) {
        const double x = q.centre_x - half + a * half / 10, y = q.centre_y - half + b * half / 10;
        const double h = bilinear_valid(depth.values, g, x, y);
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
      const double h = bilinear_valid(depth.values, g, e, n);
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
