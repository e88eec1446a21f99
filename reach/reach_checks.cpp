#include "reach/reach_checks.h"

#include <algorithm>
#include <cmath>

#include "common/config_error.h"
#include "common/number_text.h"

namespace reach {

namespace {}  // namespace

void check_elevations(const Raster& r, const std::string& raster_file, const std::string& file) {
  for (int j = 0; j < r.grid.ny; ++j)
    for (int i = 0; i < r.grid.nx; ++i) {
      const double z = r.values[r.grid.at(i, j)];
      if (std::isnan(z) || (z >= kLowestGround && z <= kHighestGround)) continue;
      throw ConfigError(file, "/terrain/file",
                        raster_file + " has an elevation of " + common::number_text(z) + " m at (" +
                            common::number_text(r.grid.x(i)) + ", " +
                            common::number_text(r.grid.y(j)) + "), beyond any ground (" +
                            common::number_text(kLowestGround) + " to " +
                            common::number_text(kHighestGround) +
                            " m): mark such cells as the raster's nodata value");
    }
}

void check_metres(const std::string& wkt, const std::string& file, const std::string& pointer,
                  const std::string& what) {
  const LinearUnit unit = crs_linear_unit(wkt);
  if (std::abs(unit.metres - 1) <= 1e-9) return;
  throw ConfigError(file, pointer,
                    what + " is in " + (unit.name.empty() ? "an unknown unit" : unit.name) + " (" +
                        common::number_text(unit.metres) +
                        " m), not metres: the grid's cells must be in metres; warp it to a "
                        "metric CRS first (gdalwarp -t_srs EPSG:...)");
}

void check_covers(const SeriesConfig& s, const Hydrograph& h, double end_time,
                  const std::string& file, const std::string& pointer) {
  if (s.value) return;
  const double first = h.points().front().first, last = h.points().back().first;
  if (first > 0 || last < end_time)
    throw ConfigError(
        file, pointer,
        "the series covers " + common::number_text(first) + " to " + common::number_text(last) +
            " s, but the run goes from 0 to /end_time = " + common::number_text(end_time) +
            " s: extend it (or shorten the run)");
}

void check_sections_apart(const std::vector<std::pair<Section, std::string>>& placed,
                          const std::string& file) {
  for (size_t a = 0; a < placed.size(); ++a)
    for (size_t b = a + 1; b < placed.size(); ++b) {
      const Section &s = placed[a].first, &t = placed[b].first;
      if (s.side != t.side || s.last < t.first || t.last < s.first) continue;
      throw ConfigError(file, placed[b].second,
                        "shares the cells " + std::to_string(std::max(s.first, t.first)) + " to " +
                            std::to_string(std::min(s.last, t.last)) + " of its side with " +
                            placed[a].second + ": move one of them");
    }
}

// The speed of the waves critical flow carries at discharge q per unit width (m/s): u + c with
// u = c = sqrt(g h_c), h_c = (q^2 / g)^(1/3).
double critical_wave_speed(double q) {
  constexpr double g = 9.81;
  const double h = std::cbrt(q * q / g);
  return 2 * std::sqrt(g * h);
}

void check_terrain_size(const Raster& header, const TerrainConfig& t, double memory_bytes,
                        const std::string& file) {
  const Grid& g = header.grid;
  CellBlock block{0, g.nx - 1, 0, g.ny - 1};
  if (!t.window.empty()) {
    block = cells_within(g, t.window[0], t.window[1], t.window[2], t.window[3]);
    if (block.empty())
      throw ConfigError(file, "/terrain/window",
                        "no cell of " + t.file + " lies inside it (the raster spans x " +
                            common::number_text(g.x0) + " to " +
                            common::number_text(g.x0 + g.nx * g.dx) + ", y " +
                            common::number_text(g.y0) + " to " +
                            common::number_text(g.y0 + g.ny * g.dy) + ")");
  }
  // Read a strip of `coarsen` rows at a time into the coarse grid; run on the coarse grid.
  const double coarse = std::ceil((block.i1 - block.i0 + 1) / double(t.coarsen)) *
                        std::ceil((block.j1 - block.j0 + 1) / double(t.coarsen));
  const double strip = double(block.i1 - block.i0 + 1) * t.coarsen;
  const double read = (strip + coarse) * kBytesPerCellRead * (t.manning_file.empty() ? 1 : 2);
  const double run = coarse * kBytesPerReachCell;
  if (read + run <= memory_bytes) return;
  throw ConfigError(file, t.window.empty() || read > run ? "/terrain/window" : "/terrain/coarsen",
                    common::number_text(block.cells()) + " cells of " + t.file + " need " +
                        common::number_text(read / 1e9) + " GB to read and " +
                        common::number_text(run / 1e9) + " GB to run (coarsened " +
                        std::to_string(t.coarsen) + " times), this process may use " +
                        common::number_text(memory_bytes / 1e9) +
                        " GB: run a smaller /terrain/window or a larger /terrain/coarsen");
}

void check_carried(double peak, double width, const std::string& file, const std::string& pointer) {
  const double depth = std::cbrt(peak * peak / (width * width) / 9.81);
  if (depth <= kDeepestCriticalFlow) return;
  throw ConfigError(file, pointer,
                    "a peak of " + common::number_text(peak) + " m^3/s over " +
                        common::number_text(width) + " m would run " + common::number_text(depth) +
                        " m deep at critical flow, deeper than "
                        "any river (" +
                        common::number_text(kDeepestCriticalFlow) + " m): check the units");
}

double check_run_length(const ReachConfig& c, const ReachModel& m, const std::string& file) {
  const Grid& g = m.solver->grid();
  const double frames = c.end_time / c.output_every;
  if (frames > kMaxReachFrames)
    throw ConfigError(file, "/output_every",
                      "the run would write " + common::number_text(frames) +
                          " frames (end_time / " + "output_every), above " +
                          common::number_text(kMaxReachFrames) + ": write them less often");
  const double cfl_step = m.wave_speed > 0 ? c.cfl * std::min(g.dx, g.dy) / m.wave_speed : c.max_dt;
  const double step = std::min(c.max_dt, cfl_step);
  const double steps = std::ceil(c.end_time / step);
  if (steps <= c.max_steps) return steps;
  const std::string key = step == c.max_dt ? "/max_dt" : c.cfl < 0.05 ? "/cfl" : m.wave_speed_key;
  throw ConfigError(
      file, key,
      "the run would take at least " + common::number_text(steps) + " steps of at most " +
          common::number_text(step) + " s to reach /end_time = " + common::number_text(c.end_time) +
          " s (waves of " + common::number_text(m.wave_speed) + " m/s from " + m.wave_speed_key +
          " on " + common::number_text(std::min(g.dx, g.dy)) + " m cells at /cfl = " +
          common::number_text(c.cfl) + "), above /max_steps = " + common::number_text(c.max_steps) +
          ": check this value, or raise /max_steps to run it");
}

}  // namespace reach
