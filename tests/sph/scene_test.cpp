// Scene files: every shipped scene loads; each kind of bad input is a ConfigError that names the
// file and the JSON pointer; the spill-sim executable turns it into a non-zero exit and writes
// nothing.

#include "sph/scene/scene_loader.h"
#include "sph/solvers/dfsph_solver.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "sph/core/config.h"
#include "sph/scene/scene_size.h"
#include "sph/simulation/simulation.h"
#include "sph/solvers/pressure_solver.h"

namespace sph {
namespace {

namespace fs = std::filesystem;
const std::string kScenes = std::string(SPILL_SOURCE_DIR) + "/configs/scenes";

nlohmann::json minimal_scene() {
  return nlohmann::json::parse(R"({
    "particle_radius": 0.05, "end_time": 0.1,
    "boxes": [{"min": [0, 0, 0], "max": [1, 1, 1]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}]})");
}

// Expects parse_scene(j) to fail with a message naming "test.json:<pointer>" and `words`.
void expect_error(const nlohmann::json& j, const std::string& pointer, const std::string& words) {
  try {
    parse_scene(j, "test.json");
    FAIL() << "expected a ConfigError at " << pointer;
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.pointer(), pointer) << e.what();
    EXPECT_NE(std::string(e.what()).find("test.json:" + pointer + ": "), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(Scene, EveryShippedSceneLoads) {
  int shipped = 0, count = 0;
  for (const auto& entry : fs::directory_iterator(kScenes))
    shipped += entry.path().extension() == ".json" ? 1 : 0;
  for (const auto& entry : fs::directory_iterator(kScenes)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const LoadedScene s = load_scene(entry.path().string());
    EXPECT_GT(s.config.particle_radius, 0);
    // Something brings fluid: a block, an emitter or a terrain filled with water.
    EXPECT_GT(Simulation(s.config).fluid().size(), 0u);
    // The resolved copy reloads to the same resolved copy (nothing lost, nothing invented).
    EXPECT_EQ(parse_scene(s.resolved, "resolved").resolved, s.resolved);
    ++count;
  }
  EXPECT_GT(shipped, 0);
  EXPECT_EQ(count, shipped);
}

TEST(Scene, DamBreakMatchesTheBenchmarkSetUp) {
  const SceneConfig s = load_scene(kScenes + "/dam_break.json").config;
  EXPECT_EQ(s.solver, "dfsph");
  EXPECT_FLOAT_EQ(s.particle_radius, 0.025f);
  EXPECT_FLOAT_EQ(s.settings<DfsphConfig>("dfsph").density_error_percent, 0.05f);
  EXPECT_FLOAT_EQ(s.settings<DfsphConfig>("dfsph").divergence_error_percent, 0.1f);
  EXPECT_FLOAT_EQ(s.time_step.dt_max, 0.005f);
  EXPECT_FLOAT_EQ(s.end_time, 4.0f);
  EXPECT_FLOAT_EQ(s.gravity[2], -9.81f);
}

TEST(Scene, DefaultsAreFilledIn) {
  const LoadedScene s = parse_scene(minimal_scene(), "test.json");
  EXPECT_EQ(s.config.solver, "dfsph");
  EXPECT_EQ(s.resolved["dfsph"]["max_iterations"], 100);
  EXPECT_EQ(s.resolved["boxes"][0]["fluid_side"], "inside");
}

TEST(Scene, UnknownKeyIsAnError) {
  auto j = minimal_scene();
  j["materials"] = {{"water", {{"viscosityy", 0.1}}}};
  expect_error(j, "/materials/water/viscosityy", "unknown key");
  j = minimal_scene();
  j["boxes"][0]["colour"] = "red";
  expect_error(j, "/boxes/0/colour", "unknown key");
}

TEST(Scene, WrongTypeIsAnError) {
  auto j = minimal_scene();
  j["particle_radius"] = "small";
  expect_error(j, "/particle_radius", "expected a number, got a string");
  j = minimal_scene();
  j["gravity"] = {0, -9.81};
  expect_error(j, "/gravity", "expected an array of 3 numbers");
  j = minimal_scene();
  j["dfsph"] = {{"max_iterations", 2.5}};
  expect_error(j, "/dfsph/max_iterations", "expected an integer");
  j = minimal_scene();
  j["dfsph"] = {{"warm_start", 1}};
  expect_error(j, "/dfsph/warm_start", "expected true or false");
}

TEST(Scene, OutOfRangeIsAnError) {
  auto j = minimal_scene();
  j["materials"] = {{"oil", {{"viscosity", -0.1}}}};
  expect_error(j, "/materials/oil/viscosity", "expected >= 0, got -0.1");
  j = minimal_scene();
  j["particle_radius"] = 0;
  expect_error(j, "/particle_radius", "expected > 0, got 0");
  j = minimal_scene();
  j["solver"] = "sph9000";
  expect_error(j, "/solver", "expected one of [dfsph, iisph, mtdf, pbf, pfsph, wcsph]");
  j = minimal_scene();
  j["boxes"][0]["max"] = {1, -1, 1};
  expect_error(j, "/boxes/0/max/1", "expected max > min");
  j = minimal_scene();
  j["time_step"] = {{"dt_min", 0.1}, {"dt_max", 0.01}};
  expect_error(j, "/time_step/dt_min", "expected <= dt_max");
}

TEST(Scene, FractionsMustSumToOne) {
  auto j = minimal_scene();
  j["fluid_blocks"][0]["fractions"] = {{"water", 0.5}, {"oil", 0.6}};
  expect_error(j, "/fluid_blocks/0/fractions", "expected volume fractions that sum to 1");
  j["fluid_blocks"][0]["fractions"] = {{"water", 0.3}, {"oil", 0.7}};
  EXPECT_FLOAT_EQ(parse_scene(j, "test.json").config.fluid_blocks[0].oil_fraction(), 0.7f);
  j = minimal_scene();
  j["fluid_blocks"][0]["material"] = "tar";
  expect_error(j, "/fluid_blocks/0/material", "expected one of [water, oil]");
}

TEST(Scene, MissingRequiredKeyIsAnError) {
  auto j = minimal_scene();
  j.erase("particle_radius");
  expect_error(j, "/particle_radius", "missing required key");
  j = minimal_scene();
  j["fluid_blocks"][0].erase("max");
  expect_error(j, "/fluid_blocks/0/max", "missing required key");
}

TEST(Scene, SetOverridesAValueBeforeValidation) {
  const LoadedScene s =
      load_scene(kScenes + "/dam_break.json", {"/solver=wcsph", "/materials/water/viscosity=0.02"});
  EXPECT_EQ(s.config.solver, "wcsph");
  EXPECT_FLOAT_EQ(s.config.materials.water.viscosity, 0.02f);
  EXPECT_THROW(load_scene(kScenes + "/dam_break.json", {"/materials/water/viscosity=-1"}),
               ConfigError);
  EXPECT_THROW(load_scene(kScenes + "/dam_break.json", {"/nonsense=1"}), ConfigError);
  EXPECT_THROW(load_scene(kScenes + "/dam_break.json", {"solver"}), ConfigError);
}

TEST(Scene, MissingOrMalformedFileIsAnError) {
  try {
    load_scene("/nonexistent/scene.json");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.json"), std::string::npos);
  }
  const fs::path bad = fs::temp_directory_path() / "spill_bad_scene.json";
  std::ofstream(bad) << "{\"particle_radius\": 0.05,";
  try {
    load_scene(bad.string());
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("not valid JSON"), std::string::npos) << e.what();
  }
}

TEST(Scene, ExecutableReportsBadSceneAndWritesNothing) {
  const fs::path dir = fs::temp_directory_path() / "spill_cli_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto j = minimal_scene();
  j["materials"] = {{"water", {{"viscosity", -0.1}}}};
  std::ofstream(dir / "bad.json") << j.dump();
  const std::string cmd = std::string(SPILL_SIM_EXE) + " run --scene " +
                          (dir / "bad.json").string() + " --out " + (dir / "out").string() +
                          " 2> " + (dir / "err.txt").string();
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);  // bad input (common/exit_codes.h)
  std::ifstream err(dir / "err.txt");
  const std::string message((std::istreambuf_iterator<char>(err)),
                            std::istreambuf_iterator<char>());
  EXPECT_NE(message.find("bad.json:/materials/water/viscosity: expected >= 0, got -0.1"),
            std::string::npos)
      << message;
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

// Inputs that once passed silently or crashed: each is a ConfigError naming the file and the key.
TEST(Scene, ValuesThatCannotRunAreRefusedNamingTheKey) {
  auto j = minimal_scene();
  // A viscosity whose stable step is below dt_min (here 1.25e-6 s; water at 100 m^2/s in the
  // hydrostatic scene: 7.8e-7 s) used to override
  // dt_min silently and blow up.
  j["materials"] = {{"water", {{"viscosity", 1000}}}};
  expect_error(j, "/materials/water/viscosity", "below /time_step/dt_min");
  j = minimal_scene();
  j["boundary"] = {{"friction", 1e3}};
  expect_error(j, "/boundary/friction", "below /time_step/dt_min");
  // The oil's viscosity counts only where there is oil.
  j = minimal_scene();
  j["materials"] = {{"oil", {{"viscosity", 1000}}}};
  EXPECT_NO_THROW(parse_scene(j, "test.json"));
  j["fluid_blocks"][0]["material"] = "oil";
  expect_error(j, "/materials/oil/viscosity", "below /time_step/dt_min");
  // Frame counts that overflow an int, and an end time between two frames.
  j = minimal_scene();
  j["end_time"] = 1.1e8;
  expect_error(j, "/end_time", "at most 10,000,000 frames");
  j = minimal_scene();
  j["end_time"] = 0.103;
  j["output"] = {{"frame_dt", 0.02}};
  expect_error(j, "/end_time", "whole number of frames");
  // A rate whose particle count wrapped the 32-bit layer count to zero (it emitted nothing).
  j = minimal_scene();
  j["emitters"] = {{{"centre", {0.5, 0.5, 0.8}}, {"rate", 1e7}, {"stop", 1.0}, {"speed", 1e12}}};
  expect_error(j, "/emitters/0/rate", "particles");
  // A direction too short to normalise in float gave NaN outlet positions (found by the fuzzer).
  j["emitters"][0]["rate"] = 0.001;
  j["emitters"][0]["direction"] = {0, 0, -1e-30};
  expect_error(j, "/emitters/0/direction", "length between");
  // A fluid block thinner than a particle diameter held no particle, silently (the whole scene
  // ran with no fluid, exit 0), and a radius of 1e308 made the support radius infinite.
  j = minimal_scene();
  j["particle_radius"] = 0.3;
  expect_error(j, "/fluid_blocks/0", "thinner than one particle diameter");
  j["particle_radius"] = 1e308;
  expect_error(j, "/particle_radius", "expected <= 10");
  // A number JSON cannot hold, and a scene path that is a folder.
  const std::string hydrostatic = kScenes + "/hydrostatic.json";
  try {
    load_scene(hydrostatic, {"/end_time=1e400"});
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.pointer(), "/end_time");
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
  try {
    load_scene(kScenes);
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("is a folder"), std::string::npos) << e.what();
  }
}

// The size estimate that refuses oversized scenes before allocating: within a factor of two of
// what every shipped scene really allocates (fluid, including emitter and inflow reserves, and
// boundary particles), so it neither lets a huge scene through nor refuses a real one.
TEST(Scene, ParticleEstimateIsWithinAFactorTwoOfEveryShippedScene) {
  for (const auto& entry : fs::directory_iterator(kScenes)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const LoadedScene s = load_scene(entry.path().string());
    double estimate = 0;
    for (const auto& part : estimate_particles(s.config)) estimate += part.particles;
    const Simulation sim(s.config);
    const double actual = double(sim.fluid().size()) + double(sim.boundary().size());
    EXPECT_GT(estimate, 0.5 * actual);
    EXPECT_LT(estimate, 2.0 * actual);
  }
}

// Scenes too large for the machine once overflowed an int and crashed (a 1e9 m wide river) or
// grew without output (particle_radius 1e-4 on the tank: 11 GB); they are refused before anything
// is allocated, naming the key.
TEST(Scene, ScenesTooLargeForTheMachineAreRefusedNamingTheKey) {
  const std::string river = kScenes + "/river_small.json";
  auto expect_refused = [](const std::string& scene, const std::vector<std::string>& set,
                           const std::string& pointer, const std::string& words) {
    try {
      load_scene(scene, set);
      ADD_FAILURE() << "expected a ConfigError at " << pointer;
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.pointer(), pointer) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  for (const char* key : {"width", "bend_amplitude", "bank_height", "floodplain", "length"})
    expect_refused(river, {std::string("/terrain/river/") + key + "=1e9"},
                   std::string("/terrain/river/") + key, "memory");
  expect_refused(river, {"/terrain/river/cell_size=1e-6"}, "/terrain/river/cell_size", "memory");
  expect_refused(river, {"/leaks/0/rate=1e6"}, "/leaks/0/rate", "particles");
  expect_refused(river, {"/leaks/0/radius=1e9"}, "/leaks/0/radius", "particles");
  expect_refused(river, {"/domain/max/0=1e9"}, "/domain", "neighbour grid");
  expect_refused(
      kScenes + "/hydrostatic.json",
      {"/particle_radius=1e-4", "/materials/water/viscosity=0", "/time_step/dt_min=1e-9"},
      "/fluid_blocks/0", "particles");
  auto j = minimal_scene();
  j["height_fields"] = {{{"origin", {0, 0, 0}}, {"cell_size", 1e5}, {"heights", {{0, 0}, {0, 0}}}}};
  expect_error(j, "/height_fields/0", "particles");
  // The memory bound is the machine's: the tank (~4k particles, ~3 MB) fits in 1 GB, not in 1 MB.
  const LoadedScene tank = load_scene(kScenes + "/hydrostatic.json");
  EXPECT_NO_THROW(check_scene_size(tank.config, "t.json", 1e9));
  EXPECT_THROW(check_scene_size(tank.config, "t.json", 1e6), ConfigError);
}

// Geometry beyond an explicit /domain stopped the run with "point outside the domain" and
// nothing more; it is refused naming the part.
TEST(Scene, GeometryOutsideTheDomainIsRefusedNamingThePart) {
  try {
    load_scene(kScenes + "/river_small.json", {"/domain/max/0=3"});
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.pointer(), "/terrain") << e.what();
    EXPECT_NE(std::string(e.what()).find("beyond /domain"), std::string::npos) << e.what();
  }
  auto j = minimal_scene();
  j["domain"] = {{"min", {0, 0, 0}}, {"max", {1, 1, 0.9}}};
  expect_error(j, "/boxes/0", "beyond /domain");
}

// A malformed command line is bad input like any other: exit 2, not CLI11's own codes.
TEST(Scene, BadCommandLineValuesExitTwo) {
  const std::string base = std::string(SPILL_SIM_EXE) + " run --scene " + kScenes +
                           "/hydrostatic.json --out " +
                           (fs::temp_directory_path() / "spill_bad_option").string() + " ";
  for (const char* option : {"--threads -3", "--save-state-at -1", "--no-such-option"}) {
    const int status = std::system((base + option + " > /dev/null 2>&1").c_str());
    ASSERT_TRUE(WIFEXITED(status)) << option;
    EXPECT_EQ(WEXITSTATUS(status), 2) << option;
  }
  EXPECT_FALSE(fs::exists(fs::temp_directory_path() / "spill_bad_option"));
}

// docs/scene_reference.md is `spill-sim scene-doc`'s output: regenerate it when a parameter
// changes (spill-sim scene-doc > docs/scene_reference.md).
TEST(Scene, ReferenceDocumentInDocsMatchesTheCode) {
  std::ifstream in(std::string(SPILL_SOURCE_DIR) + "/docs/scene_reference.md");
  ASSERT_TRUE(in);
  const std::string doc((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(doc, scene_reference_markdown());
}

// Each registered solver is chosen by its name alone, and its settings sections are read,
// written back and checked by their owners (DFSPH's iteration bounds).
TEST(Scene, EveryRegisteredSolverIsChosenByNameWithItsSettings) {
  for (const std::string& name : pressure_solver_names()) {
    auto j = minimal_scene();
    j["solver"] = name;
    const LoadedScene s = parse_scene(j, "test.json");
    EXPECT_EQ(make_pressure_solver(s.config.physics())->name(), name);
    for (const auto& section : pressure_solver_entry(name).sections)
      EXPECT_TRUE(s.resolved.contains(section.key)) << name << ": " << section.key;
  }
  auto j = minimal_scene();
  j["dfsph"] = {{"min_iterations_density", 5}, {"max_iterations", 4}};
  expect_error(j, "/dfsph/min_iterations_density", "expected <= /dfsph/max_iterations");
  j = minimal_scene();
  j["mixture"] = {{"drift_tua", 1}};
  expect_error(j, "/mixture/drift_tua", "unknown key");
  j = minimal_scene();
  j["dfsph"] = {{"density_error_percent", 0.2}};
  EXPECT_FLOAT_EQ(
      parse_scene(j, "test.json").config.settings<DfsphConfig>("dfsph").density_error_percent,
      0.2f);
}

TEST(Scene, ReferenceDocumentListsEveryParameter) {
  const std::string doc = scene_reference_markdown();
  for (const char* key : {"`/particle_radius`", "`/dfsph/density_error_percent`",
                          "`/boxes/N/fluid_side`", "`/time_step/cfl`", "`/domain/min`"})
    EXPECT_NE(doc.find(key), std::string::npos) << key;
}

}  // namespace
}  // namespace sph
