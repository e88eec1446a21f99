// `spill-sim run` outputs: the HDF5 data contract, metadata.json and stats.json keys, no clobbering
// without --force, and no output at all when a run fails.

#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/output_folder.h"
#include "sph/app/scene_runner.h"
#include "sph/core/config.h"
#include "sph/core/simulation_error.h"
#include "tests/common/file_size_limit.h"

namespace sph {
namespace {

namespace fs = std::filesystem;

nlohmann::json small_scene() {
  return nlohmann::json::parse(R"({
    "name": "small", "particle_radius": 0.02, "end_time": 0.1,
    "output": {"frame_dt": 0.02},
    "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}]})");
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Shape and HDF5 class/size of a dataset.
struct DatasetInfo {
  std::vector<hsize_t> dims;
  H5T_class_t type_class;
  size_t type_size;
};

DatasetInfo inspect(hid_t file, const std::string& path) {
  hid_t ds = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  EXPECT_GE(ds, 0) << path;
  hid_t space = H5Dget_space(ds);
  DatasetInfo info;
  info.dims.resize(size_t(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, info.dims.data(), nullptr);
  hid_t type = H5Dget_type(ds);
  info.type_class = H5Tget_class(type);
  info.type_size = H5Tget_size(type);
  H5Tclose(type);
  H5Sclose(space);
  H5Dclose(ds);
  return info;
}

TEST(RunOutputs, WritesTheDataContract) {
  const fs::path dir = fresh_dir("spill_run_outputs");
  RunOptions options;
  options.out_dir = dir / "run";
  options.ply = true;
  const LoadedScene scene = parse_scene(small_scene(), "small.json");
  run_scene(scene, options);

  const hsize_t n = 125, frames = 6;  // 5^3 particles; t = 0, 0.02, ..., 0.1
  hid_t file = H5Fopen((options.out_dir / "trajectory.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  auto pos = inspect(file, "00000/position");
  EXPECT_EQ(pos.dims, (std::vector<hsize_t>{frames, n, 3}));
  EXPECT_EQ(pos.type_class, H5T_FLOAT);
  EXPECT_EQ(pos.type_size, 4u);
  EXPECT_EQ(inspect(file, "00000/velocity").dims, (std::vector<hsize_t>{frames, n, 3}));
  auto time = inspect(file, "00000/time");
  EXPECT_EQ(time.dims, (std::vector<hsize_t>{frames}));
  EXPECT_EQ(time.type_size, 8u);
  auto type = inspect(file, "00000/particle_type");
  EXPECT_EQ(type.dims, (std::vector<hsize_t>{n}));
  EXPECT_EQ(type.type_class, H5T_INTEGER);
  EXPECT_EQ(type.type_size, 4u);
  auto active = inspect(file, "00000/active");
  EXPECT_EQ(active.dims, (std::vector<hsize_t>{frames, n}));
  EXPECT_EQ(active.type_size, 1u);
  auto fraction = inspect(file, "00000/volume_fraction");
  EXPECT_EQ(fraction.dims, (std::vector<hsize_t>{frames, n}));
  EXPECT_EQ(fraction.type_class, H5T_FLOAT);
  auto boundary = inspect(file, "00000/boundary_position");
  EXPECT_EQ(boundary.dims.size(), 2u);
  EXPECT_EQ(boundary.dims[1], 3u);
  EXPECT_GT(boundary.dims[0], 100u);
  // Frame times are the frame grid.
  std::vector<double> t(frames);
  hid_t ds = H5Dopen2(file, "00000/time", H5P_DEFAULT);
  H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, t.data());
  H5Dclose(ds);
  for (size_t k = 0; k < frames; ++k) EXPECT_NEAR(t[k], 0.02 * double(k), 1e-6);
  H5Fclose(file);

  nlohmann::json meta;
  std::ifstream(options.out_dir / "metadata.json") >> meta;
  for (const char* key : {"frame_dt", "frame_stride", "bounds", "particle_radius", "support_radius",
                          "gravity", "solver", "scene", "particle_types"})
    EXPECT_TRUE(meta.contains(key)) << key;
  EXPECT_EQ(meta["bounds"].size(), 3u);
  EXPECT_EQ(meta["solver"], "dfsph");
  EXPECT_EQ(meta["particle_types"]["boundary"], 2);

  nlohmann::json stats;
  std::ifstream(options.out_dir / "stats.json") >> stats;
  ASSERT_EQ(stats["frames"].size(), frames);
  for (const char* key :
       {"t", "steps", "density_error_avg", "density_error_max", "iterations_density",
        "iterations_divergence", "kinetic_energy", "active"})
    EXPECT_TRUE(stats["frames"][1].contains(key)) << key;
  for (const char* key : {"wall_s", "steps", "fluid_particles", "particle_steps_per_s"})
    EXPECT_TRUE(stats["summary"].contains(key)) << key;
  for (const char* key : {"neighbour_search", "pressure_solve", "other"})
    EXPECT_TRUE(stats["summary"]["time_split"].contains(key)) << key;
  EXPECT_GT(stats["frames"][5]["kinetic_energy"].get<double>(), 0);  // the block is falling
  // A dam break neither releases nor retires: every frame has all its particles.
  EXPECT_EQ(stats["frames"][5]["active"], stats["summary"]["fluid_particles"]);

  EXPECT_TRUE(fs::exists(options.out_dir / "ply" / "fluid_00005.ply"));
  EXPECT_TRUE(fs::exists(options.out_dir / "ply" / "boundary.ply"));
  std::ifstream ply(options.out_dir / "ply" / "fluid_00000.ply");
  std::string magic;
  ply >> magic;
  EXPECT_EQ(magic, "ply");

  // No staging folders are left behind.
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename(), "run") << "left over: " << e.path();
  fs::remove_all(dir);
}

// A river scene with a leak also writes its spill metrics (spill.json, one entry per frame) and
// their plot (spill.svg).
TEST(RunOutputs, RiverLeakWritesSpillMetrics) {
  const fs::path dir = fresh_dir("spill_run_river");
  RunOptions options;
  options.out_dir = dir / "run";
  const LoadedScene scene =
      load_scene(std::string(SPILL_SOURCE_DIR) + "/configs/scenes/river_small.json",
                 {"/end_time=0.4", "/leaks/0/start=0", "/leaks/0/duration=0.4",
                  "/watch_points=[{\"name\": \"intake\", \"x\": 3.0, \"y\": 0.0}]"});
  run_scene(scene, options);
  std::ifstream in(options.out_dir / "spill.json");
  ASSERT_TRUE(in);
  const nlohmann::json spill = nlohmann::json::parse(in);
  ASSERT_EQ(spill.at("frames").size(), 9u);  // t = 0, 0.05, ..., 0.4
  for (const char* key : {"t", "slick_area_m2", "front_distance_m", "left_bank_oiled_m",
                          "right_bank_oiled_m", "oil_released_m3", "oil_in_reach_m3"})
    EXPECT_TRUE(spill["frames"][8].contains(key)) << key;
  EXPECT_GT(spill["frames"][8]["oil_released_m3"].get<double>(), 0);
  EXPECT_TRUE(spill.at("arrival_s").contains("intake"));
  EXPECT_TRUE(fs::exists(options.out_dir / "spill.svg"));
}

// --png also encodes the frames into an MP4 when ffmpeg is installed; a stand-in ffmpeg records
// how it is called. Without ffmpeg, or when it fails, the run still succeeds, with no MP4.
TEST(RunOutputs, PngRunsBecomeAnAnimationWhenFfmpegIsThere) {
  const fs::path dir = fresh_dir("spill_run_animation");
  const fs::path bin = dir / "bin";
  fs::create_directories(bin);
  auto fake_ffmpeg = [&](int exit_code) {
    std::ofstream(bin / "ffmpeg") << "#!/bin/sh\necho \"$@\" > \"" << (dir / "args.txt").string()
                                  << "\"\nfor last; do :; done\necho video > \"$last\"\nexit "
                                  << exit_code << "\n";
    fs::permissions(bin / "ffmpeg", fs::perms::owner_all);
  };
  const std::string old_path = std::getenv("PATH") ? std::getenv("PATH") : "";
  auto run = [&](const std::string& name) {
    RunOptions options;
    options.out_dir = dir / name;
    options.png = true;
    run_scene(parse_scene(small_scene(), "small.json"), options);
    return options.out_dir;
  };
  setenv("PATH", (bin.string() + ":" + old_path).c_str(), 1);
  fake_ffmpeg(0);
  const fs::path with = run("with");
  fake_ffmpeg(1);
  const fs::path failing = run("failing");
  setenv("PATH", bin.string().c_str(), 1);
  fs::remove(bin / "ffmpeg");
  const fs::path without = run("without");
  setenv("PATH", old_path.c_str(), 1);

  EXPECT_TRUE(fs::exists(with / "side.mp4"));
  std::ifstream in(dir / "args.txt");
  std::string args;
  std::getline(in, args);
  EXPECT_NE(args.find("-framerate 50"), std::string::npos) << args;  // frames 0.02 s apart
  EXPECT_NE(args.find("-start_number 0"), std::string::npos) << args;
  EXPECT_NE(args.find("side_%05d.png"), std::string::npos) << args;
  EXPECT_FALSE(fs::exists(failing / "side.mp4"));
  EXPECT_TRUE(fs::exists(failing / "stats.json"));
  EXPECT_FALSE(fs::exists(without / "side.mp4"));
  EXPECT_TRUE(fs::exists(without / "png" / "side_00005.png"));
}

TEST(RunOutputs, ExistingFolderIsNotClobberedWithoutForce) {
  const fs::path dir = fresh_dir("spill_run_clobber");
  fs::create_directories(dir / "run");
  std::ofstream(dir / "run" / "keep.txt") << "precious";
  RunOptions options;
  options.out_dir = dir / "run";
  const LoadedScene scene = parse_scene(small_scene(), "small.json");
  EXPECT_THROW(run_scene(scene, options), common::OutputPathError);
  // --force replaces only an earlier run folder, never a folder of somebody else's.
  options.force = true;
  EXPECT_THROW(run_scene(scene, options), common::OutputPathError);
  EXPECT_TRUE(fs::exists(dir / "run" / "keep.txt"));
  options.out_dir = dir / "ours";
  run_scene(scene, options);
  std::ofstream(dir / "ours" / "mark.txt") << "from the first run";
  run_scene(scene, options);
  EXPECT_FALSE(fs::exists(dir / "ours" / "mark.txt"));
  EXPECT_TRUE(fs::exists(dir / "ours" / "trajectory.h5"));
  fs::remove_all(dir);
}

// A replacement that fails keeps the earlier run: it is removed only after the new one succeeded.
TEST(RunOutputs, FailedForcedRunKeepsTheEarlierRun) {
  const fs::path dir = fresh_dir("spill_run_keep");
  RunOptions options;
  options.out_dir = dir / "run";
  run_scene(parse_scene(small_scene(), "small.json"), options);
  auto escape = small_scene();
  escape["boxes"] = nlohmann::json::array();  // the block falls out of the domain
  escape["end_time"] = 1.0;
  options.force = true;
  EXPECT_THROW(run_scene(parse_scene(escape, "escape.json"), options), SimulationError);
  EXPECT_TRUE(fs::exists(dir / "run" / "trajectory.h5"));
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename(), "run") << "left over: " << e.path();
  fs::remove_all(dir);
}

// The reproductions as a user typed them: `--out . --force` deleted every file of the working
// folder, and `--out runs/new/` put the staging folder inside its target and lost the run.
TEST(RunOutputs, DotAndTrailingSlashOutFoldersAreSafe) {
  const fs::path dir = fresh_dir("spill_run_dot");
  std::ofstream(dir / "notes.txt") << "precious";
  const std::string scene = std::string(SPILL_SOURCE_DIR) + "/configs/scenes/hydrostatic.json";
  auto spill_sim = [&](const std::string& args) {
    const std::string command = "cd " + dir.string() + " && " + SPILL_SIM_EXE + " run --scene " +
                                scene + " --set /end_time=0.04 --set /output/frame_dt=0.02 " +
                                args + " > log.txt 2>&1";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(spill_sim("--out . --force"), 2);
  EXPECT_EQ(spill_sim("--out ./ --force"), 2);
  EXPECT_TRUE(fs::exists(dir / "notes.txt"));
  std::ifstream log(dir / "log.txt");
  const std::string message((std::istreambuf_iterator<char>(log)), {});
  EXPECT_NE(message.find("current folder"), std::string::npos) << message;

  EXPECT_EQ(spill_sim("--out runs/new/"), 0);
  EXPECT_TRUE(fs::exists(dir / "runs" / "new" / "trajectory.h5"));
  EXPECT_EQ(spill_sim("--out runs/new/ --force"), 0);
  EXPECT_TRUE(fs::exists(dir / "runs" / "new" / "trajectory.h5"));
  for (const auto& e : fs::directory_iterator(dir / "runs"))
    EXPECT_EQ(e.path().filename(), "new") << "left over: " << e.path();
  fs::remove_all(dir);
}

// A library call leaves process-wide state alone: the trajectory writer silences HDF5's error
// printing (it reports errors itself, naming the file) only while it calls HDF5.
TEST(RunOutputs, Hdf5ErrorPrintingIsRestoredAfterARun) {
  H5E_auto2_t before = nullptr;
  void* before_data = nullptr;
  H5Eget_auto2(H5E_DEFAULT, &before, &before_data);
  ASSERT_NE(before, nullptr);  // HDF5 prints its error stack by default
  const fs::path dir = fresh_dir("spill_run_hdf5_errors");
  RunOptions options;
  options.out_dir = dir / "run";
  run_scene(parse_scene(small_scene(), "small.json"), options);
  H5E_auto2_t after = nullptr;
  void* after_data = nullptr;
  H5Eget_auto2(H5E_DEFAULT, &after, &after_data);
  EXPECT_EQ(after, before);
  EXPECT_EQ(after_data, before_data);
  fs::remove_all(dir);
}

TEST(RunOutputs, ParticleLeavingTheDomainStopsTheRunAndWritesNothing) {
  const fs::path dir = fresh_dir("spill_run_escape");
  auto j = small_scene();
  j["boxes"] = nlohmann::json::array();  // nothing holds the block: it falls out of the domain
  j["end_time"] = 1.0;
  RunOptions options;
  options.out_dir = dir / "run";
  try {
    run_scene(parse_scene(j, "escape.json"), options);
    FAIL() << "expected SimulationError";
  } catch (const SimulationError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("left the domain"), std::string::npos) << m;
    EXPECT_NE(m.find("frame "), std::string::npos) << m;
    EXPECT_NE(m.find("particle "), std::string::npos) << m;
  }
  EXPECT_TRUE(fs::is_empty(dir)) << "no output and no staging folder may remain";
  fs::remove_all(dir);
}

// A full disk, reached at the first file, at a picture and at the trajectory: the command exits
// 1 naming the file (it used to segfault in HDF5's exit handler after "failed to close the
// file") and leaves neither the run folder nor a staging folder. The same for `generate`.
TEST(RunOutputs, AFullDiskIsAnErrorNamingTheFileAndLeavesNothing) {
  const fs::path dir = fresh_dir("spill_run_full_disk");
  std::ofstream(dir / "small.json") << small_scene().dump();
  const fs::path log = fs::temp_directory_path() / "spill_run_full_disk.txt";
  const std::string sim = std::string(SPILL_SIM_EXE) + " ";
  const std::string scene = " --scene " + (dir / "small.json").string();
  const std::vector<std::string> commands = {
      sim + "run" + scene + " --out " + (dir / "out").string() + " --png",
      sim + "generate" + scene + " --trajectories 2 --split 0.5/0.5/0 --out " +
          (dir / "out").string()};
  for (const auto& command : commands)
    for (int blocks : {0, 8, 64}) {  // of 512 bytes: metadata.json, a picture, the trajectory
      SCOPED_TRACE(command + " with files limited to " + std::to_string(blocks) + " blocks");
      const auto r = testing_support::run_with_file_size_limit(command, blocks, log);
      testing_support::expect_failed_write(r, dir);
      // Only generate keeps a folder, and only for finished trajectories (to resume them); no
      // half-written file stays anywhere.
      bool finished = false;
      for (const auto& e : fs::recursive_directory_iterator(dir)) {
        EXPECT_NE(e.path().extension(), ".tmp") << "left over: " << e.path();
        finished = finished || e.path().extension() == ".h5";
      }
      for (const auto& e : fs::directory_iterator(dir)) {
        if (!(finished && e.path().filename() == "out")) {
          EXPECT_EQ(e.path().filename(), "small.json") << "left over: " << e.path();
        }
      }
      fs::remove_all(dir / "out");
    }
  fs::remove_all(dir);
}

TEST(RunOutputs, InterruptedRunWritesNothing) {
  const fs::path dir = fresh_dir("spill_run_interrupt");
  std::atomic<bool> stop{true};
  RunOptions options;
  options.out_dir = dir / "run";
  options.stop = &stop;
  EXPECT_THROW(run_scene(parse_scene(small_scene(), "small.json"), options), RunInterrupted);
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

struct Exit {
  int code = -1;
  std::string err;
};

Exit run_sim(const std::string& arguments, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt";
  const int status = std::system(
      (std::string(SPILL_SIM_EXE) + " " + arguments + " > /dev/null 2> " + err.string()).c_str());
  std::ifstream in(err);
  std::stringstream text;
  text << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

}  // namespace

// One exit-code policy (common/exit_codes.h): each of these is bad input, exit 2, with a message
// naming the file and the key or the option (they exited 1, some naming nothing), and nothing
// is written.
TEST(RunOutputs, BadRunRequestsExitTwoNamingTheFileAndKey) {
  const fs::path dir = fresh_dir("spill_run_bad_requests");
  std::ofstream(dir / "small.json") << small_scene().dump();
  const std::string scene = "--scene " + (dir / "small.json").string();
  // A state saved at the scene's end: continuing it leaves nothing to run.
  ASSERT_EQ(
      run_sim("run " + scene + " --out " + (dir / "saved").string() + " --save-state-at 0.1", dir)
          .code,
      0);
  const std::string state = (dir / "saved" / "state.h5").string();
  struct Case {
    std::string arguments;
    std::vector<std::string> named;
    fs::path out;  // --out (default: DIR/out)
  };
  const std::vector<Case> cases = {
      {"run " + scene + " --initial-state " + state, {state + ":/time", "/end_time"}, {}},
      {"run " + scene + " --save-state-at 0.05", {"--save-state-at", "0.02"}, {}},
      {"run --scene " + std::string(SPILL_SOURCE_DIR) +
           "/configs/scenes/river_small.json --set /flow/inflow_x=-50",
       {"river_small.json:/flow/inflow_x", "crosses no water"},
       {}},
      // Readable option errors (CLI11's printed a 309-digit bound and no "error:"), empty list
      // items refused (they were dropped silently), a block outside every tank refused.
      {"run " + scene + " --threads -3", {"--threads: expected a number above 0, got -3"}, {}},
      {"run " + scene + " --threads many", {"--threads", "\"many\" (not a number)"}, {}},
      {"compare " + scene + " --solvers dfsph,,wcsph --frames 2",
       {"--solvers", "item 2 is empty"},
       {}},
      {"compare " + scene + " --solvers dfsph --frames 1,,2", {"--frames", "item 2 is empty"}, {}},
      {"run " + scene +
           " --set /fluid_blocks/0/min=[1,1,1] --set /fluid_blocks/0/max=[1.2,1.2,1.2]",
       {"small.json:/fluid_blocks/0", "outside every box"},
       {}},
      {"generate " + scene + " --trajectories 2 --split 0.5/0.5/0",
       {"--out", "cannot create"},
       dir / "small.json" / "data"},
  };
  // A leak after the end is what a warm-up run wants: it runs, and says the leak releases
  // nothing (it was silent).
  const Exit warm_up =
      run_sim("run --scene " + std::string(SPILL_SOURCE_DIR) +
                  "/configs/scenes/river_small.json --set /end_time=0.05 --set /leaks/0/start=1 " +
                  "--threads 1 --out " + (dir / "warm_up").string(),
              dir);
  EXPECT_EQ(warm_up.code, 0) << warm_up.err;
  EXPECT_NE(warm_up.err.find("note: /leaks/0 starts at 1 s, at or after /end_time"),
            std::string::npos)
      << warm_up.err;
  for (const Case& c : cases) {
    const fs::path out = c.out.empty() ? dir / "out" : c.out;
    const Exit e = run_sim(c.arguments + " --out " + out.string(), dir);
    EXPECT_EQ(e.code, 2) << c.arguments << "\n" << e.err;
    EXPECT_NE(e.err.find("error: "), std::string::npos) << e.err;
    for (const auto& word : c.named) EXPECT_NE(e.err.find(word), std::string::npos) << e.err;
    EXPECT_FALSE(fs::exists(dir / "out")) << c.arguments;
  }
  fs::remove_all(dir);
}

}  // namespace sph
