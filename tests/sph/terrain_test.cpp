// River terrain: the built-in generator builds the reaches it promises, height maps read back
// what was written (ESRI ASCII and 16-bit PNG, north row first), bad maps are clear errors, and a
// water-filled terrain holds water only in the river, above the ground and below the level.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <string>

#include "sph/core/config.h"
#include "sph/river/height_map_io.h"
#include "sph/river/leak.h"
#include "sph/river/river_generator.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"

namespace sph {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("spill_terrain_test_" + name);
}

// Width of the water mask across the river at x, and the middle of the wet cells.
std::pair<Real, Real> wet_width_and_centre(const Terrain& t, Real x) {
  const int ix = int(std::lround((x - t.origin_x) / t.cell_size));
  int wet = 0;
  Real y_sum = 0;
  for (int iy = 0; iy < t.ny; ++iy)
    if (t.water[size_t(iy) * size_t(t.nx) + size_t(ix)]) {
      ++wet;
      y_sum += t.origin_y + t.cell_size * Real(iy);
    }
  return {Real(wet) * t.cell_size, wet ? y_sum / Real(wet) : Real(0)};
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RiverGenerator, BuildsTheReachesItsParametersDescribe) {
  RiverGeneratorConfig c;  // 8 m long, 2 m wide, 0.3 m deep, bend 0.6 m, x0.7 and x1.4 reaches
  const Terrain t = generate_river(c);
  const Real cell = c.cell_size;
  // Each reach's width at the surface, measured on the mask, to within a cell on either bank.
  EXPECT_NEAR(wet_width_and_centre(t, Real(0.1) * c.length).first, c.width, 2 * cell);
  EXPECT_NEAR(wet_width_and_centre(t, Real(0.625) * c.length).first, c.narrowing * c.width,
              2 * cell);
  EXPECT_NEAR(wet_width_and_centre(t, Real(0.97) * c.length).first, c.widening * c.width, 2 * cell);
  // The bend swings the channel towards +y (the left bank) by bend_amplitude at its middle.
  EXPECT_NEAR(wet_width_and_centre(t, Real(0.375) * c.length).second, c.bend_amplitude, cell);
  EXPECT_NEAR(wet_width_and_centre(t, Real(0.1) * c.length).second, 0, cell);
  // The bed lies `depth` below the surface (to the roughness), the banks rise to bank_height.
  EXPECT_NEAR(t.height_at(Real(0.1) * c.length, 0), -c.depth, c.bed_roughness);
  EXPECT_NEAR(t.height_at(Real(0.1) * c.length, t.max_y()), c.bank_height, 1e-5);
  EXPECT_NEAR(t.height_at(Real(0.1) * c.length, t.origin_y), c.bank_height, 1e-5);
  EXPECT_NEAR(t.max_height(), c.bank_height, 1e-5);
  EXPECT_GE(t.min_height(), -c.depth - c.bed_roughness - Real(1e-5));
}

TEST(RiverGenerator, SeedChangesTheBedOnly) {
  RiverGeneratorConfig a, b;
  b.seed = 2;
  const Terrain ta = generate_river(a), ta2 = generate_river(a), tb = generate_river(b);
  EXPECT_EQ(ta.height, ta2.height);  // reproducible from the seed
  EXPECT_EQ(ta.water, tb.water);     // same channel
  double differ = 0;
  for (size_t k = 0; k < ta.height.size(); ++k)
    differ = std::max(differ, double(std::abs(ta.height[k] - tb.height[k])));
  EXPECT_GT(differ, 0.2 * double(a.bed_roughness));
  EXPECT_LE(differ, 2 * double(a.bed_roughness) + 1e-6);
}

TEST(HeightMap, EsriAsciiGridReadsNorthRowFirst) {
  const fs::path path = temp_file("grid.asc");
  std::ofstream(path) << "ncols 3\nnrows 2\nxllcorner 10\nyllcorner 20\ncellsize 0.5\n"
                         "NODATA_value -9999\n1 2 3\n4 5 6\n";
  const Terrain t = read_esri_ascii(path.string());
  ASSERT_EQ(t.nx, 3);
  ASSERT_EQ(t.ny, 2);
  EXPECT_FLOAT_EQ(t.origin_x, 10.25f);  // corner reference: centres half a cell in
  EXPECT_FLOAT_EQ(t.origin_y, 20.25f);
  EXPECT_FLOAT_EQ(t.at(0, 0), 4);  // south-west: first value of the last (southern) row
  EXPECT_FLOAT_EQ(t.at(2, 1), 3);  // north-east: last value of the first row
  // Written and read back unchanged.
  const fs::path copy = temp_file("copy.asc");
  write_esri_ascii(copy.string(), t);
  const Terrain back = read_esri_ascii(copy.string());
  EXPECT_EQ(back.height, t.height);
  EXPECT_FLOAT_EQ(back.origin_x, t.origin_x);
}

TEST(HeightMap, BadGridsNameTheFileAndTheCell) {
  const fs::path path = temp_file("bad.asc");
  const std::string header = "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
  auto read = [&] { read_esri_ascii(path.string()); };
  std::ofstream(path) << header << "NODATA_value -9999\n1 2 3\n4 -9999 6\n";
  std::string e = error_of(read);
  EXPECT_NE(e.find(path.string()), std::string::npos) << e;
  EXPECT_NE(e.find("row 2, column 2"), std::string::npos) << e;
  EXPECT_NE(e.find("NODATA"), std::string::npos) << e;
  std::ofstream(path) << header << "1 nan 3\n4 5 6\n";
  e = error_of(read);
  EXPECT_NE(e.find("row 1, column 2"), std::string::npos) << e;
  std::ofstream(path) << header << "1 2 3\n4 5\n";
  EXPECT_NE(error_of(read).find("ends early"), std::string::npos);
  std::ofstream(path) << "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\n1 2 3\n4 5 6\n";
  EXPECT_NE(error_of(read).find("cellsize"), std::string::npos);
  EXPECT_NE(error_of([] { read_esri_ascii("/nonexistent/terrain.asc"); }).find("cannot open"),
            std::string::npos);
}

TEST(HeightMap, SixteenBitPngRoundTripsToItsQuantisation) {
  const Terrain t = generate_river(RiverGeneratorConfig{});
  const fs::path path = temp_file("river.png");
  const Real lo = -0.5f, hi = 0.5f;
  write_height_png(path.string(), t, lo, hi);
  const Terrain back = read_height_png(path.string(), t.origin_x, t.origin_y, t.cell_size, lo, hi);
  ASSERT_EQ(back.nx, t.nx);
  ASSERT_EQ(back.ny, t.ny);
  double worst = 0;
  for (size_t k = 0; k < t.height.size(); ++k)
    worst = std::max(worst, double(std::abs(back.height[k] - t.height[k])));
  EXPECT_LT(worst, 0.51 * double(hi - lo) / 65535 + 1e-6);
  // A mask of another size is refused.
  Terrain other = t;
  other.nx -= 1;
  other.height.resize(size_t(other.nx) * size_t(other.ny));
  EXPECT_NE(error_of([&] { read_water_mask_png(path.string(), other); }).find("pixels"),
            std::string::npos);
}

// Scene with the generated river, shortened, filled with water and closed by two end walls.
nlohmann::json river_scene(Real length) {
  nlohmann::json j = nlohmann::json::parse(R"({
    "name": "river_fill", "solver": "dfsph", "particle_radius": 0.025, "end_time": 0.02,
    "terrain": {"source": "river", "fill_water": true, "water_level": 0}})");
  j["terrain"]["river"]["length"] = length;
  j["boxes"] = {{{"min", {-0.2, -2.5, -0.5}}, {"max", {0, 2.5, 0.3}}, {"fluid_side", "outside"}},
                {{"min", {length, -2.5, -0.5}},
                 {"max", {length + 0.2, 2.5, 0.3}},
                 {"fluid_side", "outside"}}};
  return j;
}

TEST(TerrainScene, WaterFillsTheRiverOnlyAboveTheGroundAndBelowTheLevel) {
  const LoadedScene scene = parse_scene(river_scene(2), "river_fill");
  ASSERT_TRUE(scene.config.terrain_grid);
  const Terrain& t = *scene.config.terrain_grid;
  const Simulation sim(scene.config);
  const FluidParticles& f = sim.fluid();
  ASSERT_GT(f.active_count(), 1000u);
  const Real r = scene.config.particle_radius;
  Real deepest = 0, highest = -1;
  for (Index i = 0; i < f.active_count(); ++i) {
    const Vec3& p = f.position[i];
    ASSERT_TRUE(t.is_water(p.x(), p.y())) << "particle " << i << " outside the river";
    ASSERT_GE(p.z() - r, t.height_at(p.x(), p.y()) - 1e-5) << "particle " << i;
    ASSERT_LE(p.z(), Real(1e-5)) << "particle " << i << " above the water level";
    deepest = std::min(deepest, p.z());
    highest = std::max(highest, p.z());
  }
  // It reaches the bed: the deepest particle's cell within a diameter (and the bed's slope
  // across half a cell) of the lowest ground; and the top layer within half a spacing of the
  // water level.
  EXPECT_LT(deepest - r - t.min_height(), 3 * r);
  EXPECT_NEAR(highest + r, 0, r + 1e-5);
  // The water's footprint seen from above covers the river's mask (to a particle on each bank).
  Real mask_area = 0;
  for (auto w : t.water) mask_area += w ? t.cell_size * t.cell_size : 0;
  // Lattice columns: centres sit half a spacing into a cell, so floor() is safe from ties.
  std::set<std::pair<long, long>> columns;
  for (Index i = 0; i < f.active_count(); ++i)
    columns.insert({long(std::floor(f.position[i].x() / (2 * r))),
                    long(std::floor(f.position[i].y() / (2 * r)))});
  const Real footprint = Real(columns.size()) * 4 * r * r;
  EXPECT_NEAR(footprint / mask_area, 1, 0.1)
      << "footprint " << footprint << " m^2, mask " << mask_area;
}

TEST(TerrainScene, BadTerrainInputsAreClearErrors) {
  nlohmann::json j = river_scene(2);
  j["terrain"] = {{"source", "asc"}};
  EXPECT_NE(error_of([&] { parse_scene(j, "s.json"); }).find("/terrain/file"), std::string::npos);
  j["terrain"]["file"] = "missing.asc";
  EXPECT_NE(error_of([&] { parse_scene(j, "/tmp/s.json"); }).find("/tmp/missing.asc"),
            std::string::npos);
  // A height map with NaN, found relative to the scene file.
  const fs::path map = temp_file("nan.asc");
  std::ofstream(map) << "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n0 0\nNaN 0\n";
  j["terrain"]["file"] = map.filename().string();
  const std::string e = error_of([&] { parse_scene(j, (map.parent_path() / "s.json").string()); });
  EXPECT_NE(e.find(map.string()), std::string::npos) << e;
  EXPECT_NE(e.find("row 2, column 1"), std::string::npos) << e;
  j["terrain"] = {{"source", "png"}, {"file", "x.png"}};
  EXPECT_NE(error_of([&] { parse_scene(j, "s.json"); }).find("/terrain/cell_size"),
            std::string::npos);
  j["terrain"] = {{"source", "river"}, {"river", {{"narrowing", 1.5}}}};
  EXPECT_NE(error_of([&] { parse_scene(j, "s.json"); }).find("/terrain/river/narrowing"),
            std::string::npos);
}

TEST(Leak, PositionsAcrossTheChannelAndPoursDownOntoTheWater) {
  RiverGeneratorConfig c;
  const Terrain t = generate_river(c);
  LeakConfig leak;
  leak.x = Real(0.1) * c.length;  // the straight reach, centred on y = 0
  const Real half = Real(0.5) * c.width;
  auto y_of = [&](const char* position) {
    leak.position = position;
    const EmitterConfig e = leak_emitter(leak, t, 0, "s.json", 0);
    EXPECT_EQ(e.material, "oil");
    EXPECT_FLOAT_EQ(e.direction.z(), -1);
    EXPECT_FLOAT_EQ(e.centre.z(), leak.height);
    EXPECT_FLOAT_EQ(e.stop - e.start, leak.duration);
    return e.centre.y();
  };
  // Left is +y looking downstream (+x); a bank leak is a fifth of the width in from the bank.
  EXPECT_NEAR(y_of("left_bank"), half - Real(0.2) * c.width, 2 * c.cell_size);
  EXPECT_NEAR(y_of("centre"), 0, c.cell_size);
  EXPECT_NEAR(y_of("right_bank"), -half + Real(0.2) * c.width, 2 * c.cell_size);
  // The numeric form: -1 and 1 are the banks' positions, 0.5 halfway to the left one.
  leak.lateral = 1;
  EXPECT_NEAR(y_of("centre"), half - Real(0.2) * c.width, 2 * c.cell_size);
  leak.lateral = -1;
  EXPECT_NEAR(y_of("centre"), -half + Real(0.2) * c.width, 2 * c.cell_size);
  leak.lateral = Real(0.5);
  EXPECT_NEAR(y_of("centre"), Real(0.5) * (half - Real(0.2) * c.width), 2 * c.cell_size);
}

TEST(Leak, BadLeaksAreClearErrors) {
  nlohmann::json j = river_scene(2);
  j["leaks"] = {{{"x", 5.0}}};  // the reach is 2 m long
  EXPECT_NE(error_of([&] { parse_scene(j, "s.json"); }).find("/leaks/0/x"), std::string::npos);
  j["leaks"] = {{{"x", 1.0}, {"rate", -0.001}}};
  EXPECT_NE(error_of([&] { parse_scene(j, "s.json"); }).find("/leaks/0/rate"), std::string::npos);
  j["leaks"] = {{{"x", 1.0}, {"position", "upstream"}}};
  EXPECT_NE(error_of([&] { parse_scene(j, "s.json"); }).find("/leaks/0/position"),
            std::string::npos);
  j["leaks"] = {{{"x", 1.0}}};
  j["terrain"]["water_level"] = -1.0;  // below the bed: no water anywhere
  EXPECT_NE(error_of([&] { parse_scene(j, "s.json"); }).find("no water"), std::string::npos);
  j.erase("terrain");
  EXPECT_NE(error_of([&] { parse_scene(j, "s.json"); }).find("/leaks"), std::string::npos);
}

}  // namespace
}  // namespace sph
