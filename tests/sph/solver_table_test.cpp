// `spill-sim compare`: a row per solver with wall times at each moment, a picture grid of a column
// per solver and a row per moment, a solver that blows up marked while the others finish, and bad
// requests refused before anything is written.

#include "sph/app/solver_table.h"

#include <gtest/gtest.h>
#include <png.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "common/output_folder.h"
#include "common/picture_grid.h"
#include "sph/core/config.h"
#include "sph/core/simulation_error.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/frame_loop.h"
#include "sph/simulation/simulation.h"
#include "tests/common/file_size_limit.h"

namespace sph {
namespace {

namespace fs = std::filesystem;

const std::string kDamBreak = std::string(SPILL_SOURCE_DIR) + "/configs/scenes/dam_break.json";
const std::string kRiver = std::string(SPILL_SOURCE_DIR) + "/configs/scenes/river_small.json";
// The dam break at 0.1 m spacing: 1,000 fluid particles, about a second of CPU to 0.08 s.
const std::vector<std::string> kTinyDamBreak = {"/particle_radius=0.05", "/end_time=0.08"};
// A speed of sound of 1 cm/s: WCSPH's pressure cannot hold the water up, which falls through the
// tank's floor and leaves the domain in frame 14 (t = 0.27 s). The settings are WCSPH's own, so
// the other solvers do not see them.
const std::vector<std::string> kWcsphBlowUp = {"/wcsph/expected_max_velocity=0.01",
                                               "/wcsph/sound_speed_factor=1", "/end_time=0.4"};

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  EXPECT_TRUE(in) << file;
  return nlohmann::json::parse(in);
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

common::RgbImage read_png(const fs::path& file) {
  common::RgbImage img;
  FILE* in = std::fopen(file.c_str(), "rb");
  EXPECT_NE(in, nullptr) << file;
  if (!in) return img;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(in);
    ADD_FAILURE() << file << ": not a PNG";
    return common::RgbImage{};
  }
  png_init_io(png, in);
  png_read_info(png, info);
  EXPECT_EQ(png_get_color_type(png, info), PNG_COLOR_TYPE_RGB);
  EXPECT_EQ(png_get_bit_depth(png, info), 8);
  img.width = int(png_get_image_width(png, info));
  img.height = int(png_get_image_height(png, info));
  img.pixels.resize(size_t(img.width) * size_t(img.height) * 3);
  for (int y = 0; y < img.height; ++y)
    png_read_row(png, &img.pixels[size_t(y) * size_t(img.width) * 3], nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(in);
  return img;
}

// Pixels of cell (row, column) of a grid laid out like `layout` for which `test(r, g, b)` holds.
template <class Test>
long count_in_cell(const common::RgbImage& img, const common::PictureGrid& layout, int row,
                   int column, Test test) {
  long n = 0;
  for (int y = layout.cell_y(row); y < layout.cell_y(row) + layout.cell_height(); ++y)
    for (int x = layout.cell_x(column); x < layout.cell_x(column) + layout.cell_width(); ++x) {
      const std::uint8_t* p = &img.pixels[(size_t(y) * size_t(img.width) + size_t(x)) * 3];
      n += test(int(p[0]), int(p[1]), int(p[2]));
    }
  return n;
}

bool water_blue(int r, int g, int b) {
  return b > r + 60 && b > g + 20;
}
bool oil_dark(int r, int g, int b) {
  return r < 80 && g < 70 && b < 60;
}

SolverTableRequest tiny_request(const fs::path& out) {
  SolverTableRequest r;
  r.scene_file = kDamBreak;
  r.overrides = kTinyDamBreak;
  r.solvers = {"dfsph", "wcsph"};
  r.frames = {2, 4};  // t = 0.04 s and 0.08 s
  r.out_dir = out;
  r.cell_width = 120;
  return r;
}

TEST(SolverTable, ARowPerSolverAndAViewPerSolverAndMoment) {
  const fs::path dir = fresh_dir("spill_compare_table");
  const SolverTableRequest request = tiny_request(dir / "cmp");
  const nlohmann::json returned = write_solver_table(request);

  const nlohmann::json table = read_json(dir / "cmp" / "table.json");
  EXPECT_EQ(table, returned);
  EXPECT_EQ(table.at("frames"), (std::vector<int>{2, 4}));
  EXPECT_NEAR(table.at("times_s")[1].get<double>(), 0.08, 1e-12);
  EXPECT_DOUBLE_EQ(table.at("frame_dt").get<double>(), 0.02);
  ASSERT_EQ(table.at("rows").size(), 2u);
  for (size_t s = 0; s < 2; ++s) {
    const nlohmann::json& row = table.at("rows")[s];
    SCOPED_TRACE(row.dump());
    EXPECT_EQ(row.at("solver"), request.solvers[s]);
    EXPECT_EQ(row.at("status"), "ok");
    ASSERT_EQ(row.at("wall_s").size(), 2u);
    const double w0 = row.at("wall_s")[0].get<double>(), w1 = row.at("wall_s")[1].get<double>();
    EXPECT_GT(w0, 0);
    EXPECT_GT(w1, w0);  // the wall time to a later moment includes the earlier one's
    EXPECT_DOUBLE_EQ(row.at("summary").at("wall_s").get<double>(), w1);
    EXPECT_GT(row.at("particle_steps_per_s").get<double>(), 0);
    EXPECT_EQ(row.at("fluid_particles"), 1000);  // a 1 m cube at 0.1 m spacing
    EXPECT_GE(row.at("steps").get<long>(), 16);  // 0.08 s at dt_max = 0.005 s
    EXPECT_GE(row.at("density_error_percent").get<double>(), 0);
    EXPECT_FALSE(row.contains("spill"));  // no river
    EXPECT_FALSE(row.contains("failure"));
  }
  // DFSPH iterates (at least 2 constant-density iterations a step); WCSPH is explicit.
  EXPECT_GE(table.at("rows")[0].at("iterations_density").get<double>(), 2);
  EXPECT_GT(table.at("rows")[0].at("iterations_divergence").get<double>(), 0);
  EXPECT_EQ(table.at("rows")[1].at("iterations_density").get<double>(), 0);

  // views.png: 2 columns x 2 rows of top views of the 4 x 1.5 m tank, water in every cell.
  const nlohmann::json& views = table.at("views");
  EXPECT_EQ(views.at("view"), "top");
  EXPECT_EQ(views.at("cell_width"), 120);
  // The cell has the aspect of the simulation's domain seen from above (the tank and the
  // boundary layer behind its walls).
  const Simulation sim(load_scene(kDamBreak, kTinyDamBreak).config);
  const Vec3 size = sim.domain().max - sim.domain().min;
  EXPECT_NEAR(views.at("cell_height").get<double>(), 120 * size[1] / size[0], 1);
  const common::PictureGrid layout(views.at("cell_width"), views.at("cell_height"),
                                   {"dfsph", "wcsph"}, {"t = 0.04 s", "t = 0.08 s"});
  const common::RgbImage img = read_png(dir / "cmp" / "views.png");
  EXPECT_EQ(img.width, layout.label_width() + 2 * (120 + common::PictureGrid::kGap) +
                           common::PictureGrid::kGap);
  EXPECT_EQ(img.height, layout.label_height() +
                            2 * (views.at("cell_height").get<int>() + common::PictureGrid::kGap) +
                            common::PictureGrid::kGap);
  EXPECT_EQ(views.at("width"), img.width);
  EXPECT_EQ(views.at("height"), img.height);
  ASSERT_EQ(img.pixels.size(), size_t(img.width) * size_t(img.height) * 3);
  for (int row = 0; row < 2; ++row)
    for (int column = 0; column < 2; ++column)
      EXPECT_GT(count_in_cell(img, layout, row, column, water_blue), 50)
          << "cell " << row << ", " << column;
  // The labels are drawn: ink above the columns and left of the rows.
  long ink = 0;
  for (int y = 0; y < layout.cell_y(0); ++y)
    for (int x = 0; x < img.width; ++x)
      ink += img.pixels[(size_t(y) * size_t(img.width) + size_t(x)) * 3] == 0;
  EXPECT_GT(ink, 20);

  const std::string md = read_text(dir / "cmp" / "table.md");
  for (const char* part : {"# Solver comparison: dam_break", "frame_dt: 0.02 s", "threads: 1",
                           "| dfsph | ok |", "| wcsph | ok |", "wall s to 0.08 s",
                           "columns left to right dfsph, wcsph", "rows top to bottom t = 0.04 s"})
    EXPECT_NE(md.find(part), std::string::npos) << part << "\n" << md;
  EXPECT_NE(md.find(table.at("machine").at("cpu").get<std::string>()), std::string::npos) << md;
  EXPECT_EQ(md.find("Failures"), std::string::npos) << md;

  // Nothing but the output folder remains (no staging folder).
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename(), "cmp") << "left over: " << e.path();

  // An existing folder is refused without --force, and kept.
  EXPECT_THROW(write_solver_table(request), common::OutputPathError);
  EXPECT_TRUE(fs::exists(dir / "cmp" / "views.png"));
  fs::remove_all(dir);
}

TEST(SolverTable, ASolverThatBlowsUpIsMarkedAndTheOthersFinish) {
  const fs::path dir = fresh_dir("spill_compare_blow_up");
  SolverTableRequest request = tiny_request(dir / "cmp");
  request.overrides.insert(request.overrides.end(), kWcsphBlowUp.begin(), kWcsphBlowUp.end());
  request.solvers = {"wcsph", "dfsph"};
  request.frames = {10, 20};  // t = 0.2 s, before the blow-up, and 0.4 s, after it
  write_solver_table(request);

  const nlohmann::json table = read_json(dir / "cmp" / "table.json");
  const nlohmann::json& wcsph = table.at("rows")[0];
  const nlohmann::json& dfsph = table.at("rows")[1];
  EXPECT_EQ(wcsph.at("status"), "failed");
  const int frame = wcsph.at("failure").at("frame");
  EXPECT_GT(frame, 10);
  EXPECT_LE(frame, 20);
  const double t = wcsph.at("failure").at("t_s");
  EXPECT_GE(t, 0.02 * (frame - 1) - 1e-9);
  EXPECT_LT(t, 0.02 * frame);
  const std::string reason = wcsph.at("failure").at("reason");
  EXPECT_NE(reason.find("frame " + std::to_string(frame)), std::string::npos) << reason;
  EXPECT_NE(reason.find("left the domain"), std::string::npos) << reason;
  // Its time to the moment before the blow-up is kept, the later one is not.
  EXPECT_GT(wcsph.at("wall_s")[0].get<double>(), 0);
  EXPECT_TRUE(wcsph.at("wall_s")[1].is_null());
  EXPECT_FALSE(wcsph.contains("particle_steps_per_s"));
  // The other solver is complete.
  EXPECT_EQ(dfsph.at("status"), "ok");
  EXPECT_GT(dfsph.at("wall_s")[1].get<double>(), dfsph.at("wall_s")[0].get<double>());
  EXPECT_GT(dfsph.at("iterations_density").get<double>(), 0);

  const std::string md = read_text(dir / "cmp" / "table.md");
  char failed[64];
  std::snprintf(failed, sizeof failed, "failed in frame %d (at t = %g s)", frame, t);
  EXPECT_NE(md.find("| wcsph | " + std::string(failed) + " | "), std::string::npos) << md;
  EXPECT_NE(md.find(" | – | – | – | – | – | – |\n| dfsph | ok |"), std::string::npos) << md;
  EXPECT_NE(md.find("Failures:\n\n- wcsph, " + std::string(failed) + ": " + reason),
            std::string::npos)
      << md;

  // The failed solver's cell after the blow-up is grey; before it, and in the other column,
  // there is water.
  const nlohmann::json& views = table.at("views");
  const common::PictureGrid layout(views.at("cell_width"), views.at("cell_height"),
                                   {"wcsph", "dfsph"}, {"t = 0.2 s", "t = 0.4 s"});
  const common::RgbImage img = read_png(dir / "cmp" / "views.png");
  const long cell = long(layout.cell_width()) * layout.cell_height();
  auto grey = [](int r, int g, int b) {
    return r == common::PictureGrid::kEmpty.r && g == common::PictureGrid::kEmpty.g &&
           b == common::PictureGrid::kEmpty.b;
  };
  EXPECT_GT(count_in_cell(img, layout, 0, 0, water_blue), 50);
  EXPECT_GT(count_in_cell(img, layout, 1, 0, grey), cell * 8 / 10);
  EXPECT_EQ(count_in_cell(img, layout, 1, 0, water_blue), 0);
  for (int row = 0; row < 2; ++row)
    EXPECT_GT(count_in_cell(img, layout, row, 1, water_blue), 50) << "row " << row;

  // When every solver fails, it is an error and nothing is written.
  request.out_dir = dir / "all_failed";
  request.solvers = {"wcsph"};
  try {
    write_solver_table(request);
    FAIL() << "expected SimulationError";
  } catch (const SimulationError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("every solver failed"), std::string::npos) << m;
    EXPECT_NE(m.find("wcsph failed in frame"), std::string::npos) << m;
  }
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename(), "cmp") << "left over: " << e.path();
  fs::remove_all(dir);
}

TEST(SolverTable, BadRequestsAreRefusedBeforeAnythingRunsOrIsWritten) {
  const fs::path dir = fresh_dir("spill_compare_bad");
  SolverTableRequest request = tiny_request(dir / "cmp");
  request.solvers = {"dfsph", "no_such_solver"};
  try {
    write_solver_table(request);
    FAIL() << "expected an error for an unknown solver";
  } catch (const common::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--solvers: unknown solver \"no_such_solver\""), std::string::npos) << m;
    for (const std::string& known : pressure_solver_names())
      EXPECT_NE(m.find(known), std::string::npos) << "lists " << known << ": " << m;
  }
  auto refused = [&](SolverTableRequest r, const std::string& expected) {
    try {
      write_solver_table(r);
      ADD_FAILURE() << "expected an error containing " << expected;
    } catch (const common::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  request = tiny_request(dir / "cmp");
  request.solvers = {"dfsph", "dfsph"};
  refused(request, "\"dfsph\" is named twice");
  request = tiny_request(dir / "cmp");
  request.frames = {4, 2};
  refused(request, "expected increasing frame counts");
  request.frames = {0, 2};
  refused(request, "expected frame counts >= 1");
  request.frames = {2, 5};  // the scene ends at frame 4
  refused(request, "--set /end_time=0.1");
  request = tiny_request(dir / "cmp");
  request.overrides.push_back("/materials/water/viscosity=-1");
  refused(request, "/materials/water/viscosity");
  EXPECT_TRUE(fs::is_empty(dir));

  // An interruption (Ctrl-C) leaves nothing either.
  std::atomic<bool> stop{true};
  request = tiny_request(dir / "cmp");
  request.stop = &stop;
  EXPECT_THROW(write_solver_table(request), RunInterrupted);
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

// The command line: exit 2 for an unknown solver, 0 when some solver finished, 1 when none did,
// and 1 naming the file on a full disk, with nothing left behind.
TEST(SolverTable, ExitCodesOfTheCommand) {
  const fs::path dir = fresh_dir("spill_compare_cli");
  const fs::path log = dir / "log.txt";
  auto spill_sim = [&](const std::string& solvers, const std::string& out) {
    const std::string command = std::string(SPILL_SIM_EXE) + " compare --scene " + kDamBreak +
                                " --set /particle_radius=0.05 --set " + kWcsphBlowUp[0] +
                                " --set " + kWcsphBlowUp[1] + " --set " + kWcsphBlowUp[2] +
                                " --threads 1 --frames 10,20 --solvers " + solvers + " --out " +
                                (dir / out).string() + " > " + log.string() + " 2>&1";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(spill_sim("dfsph,nope", "a"), 2);
  EXPECT_NE(read_text(log).find("unknown solver \"nope\""), std::string::npos) << read_text(log);
  EXPECT_FALSE(fs::exists(dir / "a"));
  EXPECT_EQ(spill_sim("wcsph,dfsph", "b"), 0) << read_text(log);
  EXPECT_NE(read_text(log).find("1 failed"), std::string::npos) << read_text(log);
  EXPECT_TRUE(fs::exists(dir / "b" / "views.png"));
  EXPECT_EQ(spill_sim("wcsph", "c"), 1);
  EXPECT_NE(read_text(log).find("every solver failed"), std::string::npos) << read_text(log);
  EXPECT_FALSE(fs::exists(dir / "c"));

  const fs::path full = fresh_dir("spill_compare_full_disk");
  const std::string command = std::string(SPILL_SIM_EXE) + " compare --scene " + kDamBreak +
                              " --set /particle_radius=0.05 --set /end_time=0.04 --threads 1 "
                              "--frames 2 --solvers dfsph --out " +
                              (full / "out").string();
  for (int blocks : {0, 4}) {  // of 512 bytes: table.json, then views.png
    SCOPED_TRACE("files limited to " + std::to_string(blocks) + " blocks");
    const auto r = testing_support::run_with_file_size_limit(command, blocks, log);
    testing_support::expect_failed_write(r, full);
    EXPECT_TRUE(fs::is_empty(full)) << "nothing may be left";
  }
  fs::remove_all(full);
  fs::remove_all(dir);
}

// A river leak: the run's largest slick, furthest front and bank contacts are in the row, and the
// map view shows the oil.
TEST(SolverTable, RiverLeakHasSpillMetricsAndOilInTheMapView) {
  const fs::path dir = fresh_dir("spill_compare_river");
  SolverTableRequest request;
  request.scene_file = kRiver;
  request.overrides = {"/end_time=0.3", "/leaks/0/start=0", "/leaks/0/duration=0.3"};
  request.solvers = {"dfsph"};
  request.frames = {6};
  request.out_dir = dir / "cmp";
  request.cell_width = 80;
  const nlohmann::json table = write_solver_table(request);
  const nlohmann::json& row = table.at("rows")[0];
  ASSERT_EQ(row.at("status"), "ok") << row.dump();
  const nlohmann::json& spill = row.at("spill");
  EXPECT_GT(spill.at("peak_slick_area_m2").get<double>(), 0);
  EXPECT_GT(spill.at("peak_slick_area_t_s").get<double>(), 0);
  EXPECT_LE(spill.at("peak_slick_area_t_s").get<double>(), 0.3 + 1e-9);
  EXPECT_GE(spill.at("furthest_front_m").get<double>(), 0);
  EXPECT_TRUE(spill.contains("first_left_bank_contact_s"));
  EXPECT_TRUE(spill.contains("first_right_bank_contact_s"));
  EXPECT_EQ(table.at("views").at("view"), "river");
  const std::string md = read_text(dir / "cmp" / "table.md");
  EXPECT_NE(md.find("peak slick area m² (at s)"), std::string::npos) << md;

  const nlohmann::json& views = table.at("views");
  const common::PictureGrid layout(views.at("cell_width"), views.at("cell_height"), {"dfsph"},
                                   {"t = 0.3 s"});
  const common::RgbImage img = read_png(dir / "cmp" / "views.png");
  EXPECT_EQ(img.width, views.at("width").get<int>());
  EXPECT_GT(views.at("cell_height").get<int>(), views.at("cell_width").get<int>());  // flow down
  EXPECT_GT(count_in_cell(img, layout, 0, 0, oil_dark), 0);
  EXPECT_GT(count_in_cell(img, layout, 0, 0, water_blue), 50);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sph
