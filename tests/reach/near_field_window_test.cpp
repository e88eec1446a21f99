// A near field's window on a reach run (reach/near_field_window.h), on a run folder written here by
// hand: a tilted plane of a bed under water of uniform depth moving uniformly, so that every
// sampled value is known in closed form (bilinear interpolation is exact on a plane), whatever
// the box's heading.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/config_error.h"
#include "reach/near_field_window.h"
#include "reach/raster.h"

namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kX0 = 1771000, kY0 = 5472000;

// The plane bed and the flow of the hand-written run.
double bed_at(double east, double north) {
  return 10 + 0.002 * (east - kX0) - 0.001 * (north - kY0);
}
constexpr double kDepth = 0.8, kVx = 0.6, kVy = -0.8;  // m, m/s east and north

class NearFieldWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("spill_near_field_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "rasters");
    reach::Raster r;
    r.grid.nx = 40, r.grid.ny = 30, r.grid.dx = r.grid.dy = 5;
    r.grid.x0 = kX0, r.grid.y0 = kY0;
    r.crs_wkt = reach::crs_wkt_of("EPSG:2193");
    const auto write = [&](const std::string& name, auto value) {
      r.values.clear();
      for (int j = 0; j < r.grid.ny; ++j)
        for (int i = 0; i < r.grid.nx; ++i) r.values.push_back(value(r.grid.x(i), r.grid.y(j)));
      reach::write_geotiff((dir_ / name).string(), r);
    };
    write("bed.tif", bed_at);
    // The water: uniform, except a dry strip along the south edge.
    const auto wet = [](double, double n) { return n > kY0 + 10; };
    write("rasters/depth.tif", [&](double e, double n) { return wet(e, n) ? kDepth : 0.0; });
    write("rasters/vx.tif", [&](double e, double n) { return wet(e, n) ? kVx : std::nan(""); });
    write("rasters/vy.tif", [&](double e, double n) { return wet(e, n) ? kVy : std::nan(""); });
    const nlohmann::json files = {{"depth", "rasters/depth.tif"},
                                  {"velocity_x", "rasters/vx.tif"},
                                  {"velocity_y", "rasters/vy.tif"}};
    const nlohmann::json summary = {
        {"frames", {{{"t_s", 0.0}, {"files", files}}, {{"t_s", 3600.0}, {"files", files}}}}};
    std::ofstream(dir_ / "reach.json") << summary.dump();
    request_.run_dir = dir_.string();
    request_.centre_x = kX0 + 100;
    request_.centre_y = kY0 + 80;
    request_.length = 30;
    request_.width = 20;
    request_.cell_size = 0.5;
    request_.config_file = "scene.json";
    request_.pointer = "/terrain/reach";
  }
  void TearDown() override { fs::remove_all(dir_); }
  // The message of the ConfigError sampling throws ("" when none).
  std::string refusal(const reach::NearFieldRequest& q) {
    try {
      reach::sample_near_field(q);
    } catch (const common::ConfigError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
  reach::NearFieldRequest request_;
};

}  // namespace

// With no heading given the box runs with the flow (bearing atan2(0.6, -0.8) = 143.13 deg); its
// bed is the plane at the mapped points, the velocity along it is the whole speed (1 m/s) and
// across it none; the inflow section's level and velocity are the reach's.
TEST_F(NearFieldWindow, TurnsWithTheFlowAndSamplesTheBedAndWater) {
  const reach::NearFieldWindow w = reach::sample_near_field(request_);
  EXPECT_NEAR(w.heading_deg, std::atan2(kVx, kVy) * 180 / kPi, 1e-6);
  EXPECT_EQ(w.nx, 61);
  EXPECT_EQ(w.ny, 41);
  EXPECT_DOUBLE_EQ(w.time_s, 3600.0);
  double worst_bed = 0;
  for (int j = 0; j < w.ny; ++j)
    for (int i = 0; i < w.nx; ++i) {
      double e = 0, n = 0;
      w.to_map(w.x(i), w.y(j), e, n);
      worst_bed = std::max(worst_bed, std::abs(w.bed[w.at(i, j)] - bed_at(e, n)));
      EXPECT_NEAR(w.depth[w.at(i, j)], kDepth, 1e-6);
      EXPECT_NEAR(w.along[w.at(i, j)], 1.0, 1e-6);
      EXPECT_NEAR(w.across[w.at(i, j)], 0.0, 1e-6);
    }
  EXPECT_LT(worst_bed, 1e-4);  // the GeoTIFF holds Float32
  // Map positions to 10 um: the heading comes from Float32 velocities.
  // The box's upstream end is half its length behind the centre, against the flow.
  double e = 0, n = 0;
  w.to_map(0, 0, e, n);
  EXPECT_NEAR(e, request_.centre_x - 15 * 0.6, 1e-5);
  EXPECT_NEAR(n, request_.centre_y + 15 * 0.8, 1e-5);
  // +y is the left bank looking downstream: 90 deg anticlockwise of the flow.
  w.to_map(15, 10, e, n);
  EXPECT_NEAR(e, request_.centre_x + 10 * 0.8, 1e-5);
  EXPECT_NEAR(n, request_.centre_y + 10 * 0.6, 1e-5);
  w.to_map(3, 0, e, n);
  EXPECT_NEAR(w.section_level(3, 0.01), bed_at(e, n) + kDepth, 1e-4);
  EXPECT_NEAR(w.section_velocity(3, 0.01), 1.0, 1e-6);
}

// A heading given turns the box that way: due east, the velocity along it is the east component
// and across it (towards north) the north one.
TEST_F(NearFieldWindow, AGivenHeadingSplitsTheVelocityIntoAlongAndAcross) {
  request_.heading_deg = 90;
  const reach::NearFieldWindow w = reach::sample_near_field(request_);
  EXPECT_NEAR(w.along[w.at(10, 20)], kVx, 1e-6);
  EXPECT_NEAR(w.across[w.at(10, 20)], kVy, 1e-6);
}

TEST_F(NearFieldWindow, RefusesWhatItCannotUseNamingTheKey) {
  reach::NearFieldRequest q = request_;
  q.centre_x = kX0 + 5;  // a corner leaves the grid
  EXPECT_NE(refusal(q).find("scene.json:/terrain/reach/centre: the box's corner"),
            std::string::npos);
  q = request_;
  q.centre_y = kY0 + 3;  // the heading's square (4 m wide) is dry
  q.width = 4;
  EXPECT_NE(refusal(q).find("/terrain/reach/heading"), std::string::npos);
  q.heading_deg = 90;
  EXPECT_NE(refusal(q).find("holds no water"), std::string::npos);
  q = request_;
  q.time = 100;
  EXPECT_NE(refusal(q).find("/terrain/reach/time: the reach run has no output at 100"),
            std::string::npos);
  q.time = 3600.2;
  EXPECT_EQ(refusal(q), "");
  q = request_;
  q.run_dir = (dir_ / "rasters").string();
  EXPECT_NE(refusal(q).find("/terrain/reach/run"), std::string::npos);
  fs::remove(dir_ / "bed.tif");
  EXPECT_NE(refusal(request_).find("no bed.tif"), std::string::npos);
}
