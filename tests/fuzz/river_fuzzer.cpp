// River fuzzer: mutates a small reach config (`--command reach`) or a forecast config on a
// finished reach run (`--command forecast`) as a careless or hostile user would (keys deleted,
// signs flipped, numbers scaled by 1e-9 .. 1e9, types swapped, files truncated) and runs
// `spill-sim reach` or `spill-sim forecast` on each. Every case must end in exit 0, 1 or 2 within
// the time bound, with no signal and nothing left behind when it fails; an exit 2 must name the
// config file (and with it the key). The channel is an ESRI ASCII grid written here, so the
// fuzzer needs no GDAL of its own. Prints a JSON summary; exits 1 when a case misbehaved.
//
//   river_fuzzer --sim build/sim/spill-sim --command reach --work /tmp/fuzz --cases 200

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>

#include "tests/fuzz/child_process.h"
#include "tests/fuzz/fuzz_report.h"
#include "tests/fuzz/json_mutation.h"

namespace fs = std::filesystem;

namespace {

// A channel 400 m long, its flat bed 60 m wide falling 1 in 1000 to the west between banks 2 m
// high, on 10 m cells (NZTM2000 coordinates, the config names the CRS).
void write_channel(const fs::path& file) {
  std::ofstream out(file);
  out << "ncols 40\nnrows 8\nxllcorner 1771000\nyllcorner 5472000\ncellsize 10\n"
         "NODATA_value -9999\n";
  for (int row = 0; row < 8; ++row) {
    for (int i = 0; i < 40; ++i)
      out << (i ? " " : "") << 0.001 * (10 * i + 5) + ((row == 0 || row == 7) ? 2.0 : 0.0);
    out << "\n";
  }
}

nlohmann::json reach_config() {
  return {{"name", "channel"},
          {"terrain", {{"file", "../base/channel.asc"}, {"crs", "EPSG:2193"}, {"manning", 0.03}}},
          {"inflows",
           {{{"section", {{"name", "up"}, {"side", "east"}, {"from", 5472010}, {"to", 5472070}}},
             {"discharge", {{"points", {{0, 4.0}, {600, 6.0}}}}}}}},
          {"outflows",
           {{{"section", {{"name", "down"}, {"side", "west"}, {"from", 5472010}, {"to", 5472070}}},
             {"kind", "normal_depth"},
             {"slope", 0.001}}}},
          {"end_time", 600},
          {"output_every", 300},
          {"steady_tolerance", 1e-5},
          {"steady_window", 120}};
}

// On the base reach's steady flow.
nlohmann::json forecast_config() {
  return {{"name", "channel spill"},
          {"flow", {{"reach_run", "../base/reach_run"}}},
          {"centreline", {{1771395, 5472040}, {1771005, 5472040}}},
          {"oil", "light_crude"},
          {"releases",
           {{{"position", {1771350, 5472040}},
             {"start", 0},
             {"end", 120},
             {"rate", {{"value", 0.01}}},
             {"elements", 100}}}},
          {"environment",
           {{"water_temperature", {{"value", 12}}},
            {"wind_speed", {{"points", {{0, 3}, {600, 6}}}}},
            {"wind_from", {{"value", 100}}}}},
          {"banks",
           {{"bin_length", 50},
            {"classes", {{{"name", "grass"}, {"capacity", 0.005}, {"refloat_half_life", 2}}}},
            {"default_class", "grass"}}},
          {"watch_points", {{{"name", "intake"}, {"position", {1771100, 5472040}}}}},
          {"end_time", 600},
          {"time_step", 30},
          {"output_every", 300},
          {"start_date", "2026-06-01T06:00:00Z"}};
}

// Runs are kept to two outputs so a healthy case is quick and a slow one is a hang; what the
// checks refuse (too many frames, not a number) is left for them to refuse.
void shorten(nlohmann::json& config) {
  if (!config.is_object() || !config.contains("end_time") || !config["end_time"].is_number() ||
      !config.contains("output_every") || !config["output_every"].is_number())
    return;
  const double end = config["end_time"].get<double>();
  const double every = config["output_every"].get<double>();
  if (end > 0 && every > 0 && end / every <= 1e5) config["end_time"] = std::min(end, 2 * every);
}

std::string text_of(const fs::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Reach and forecast config fuzzer for spill-sim"};
  std::string sim, work, command = "reach";
  int cases = 200;
  std::uint64_t seed = 1;
  double timeout_s = 30, memory_mb = 1024;
  bool keep = false;
  app.add_option("--sim", sim, "spill-sim executable")->required();
  app.add_option("--command", command, "reach or forecast")
      ->check(CLI::IsMember({"reach", "forecast"}));
  app.add_option("--work", work, "scratch folder (emptied)")->required();
  app.add_option("--cases", cases, "number of cases");
  app.add_option("--seed", seed, "random seed");
  app.add_option("--timeout", timeout_s, "seconds after which a case counts as hung");
  app.add_option("--memory-mb", memory_mb, "memory limit of each run (RLIMIT_DATA)");
  app.add_flag("--keep", keep, "keep every case's folder, not only failed ones");
  CLI11_PARSE(app, argc, argv);

  fs::remove_all(work);
  const fs::path base = fs::path(work) / "base";
  fs::create_directories(base);
  write_channel(base / "channel.asc");
  if (command == "forecast") {
    // The flow every forecast case runs on, made once (run to its steady state, so that its
    // last output holds for ever after); a case must never write into it.
    nlohmann::json steady = reach_config();
    steady["end_time"] = 7200;
    steady["output_every"] = 1800;
    steady["inflows"][0]["discharge"] = {{"value", 6.0}};
    std::ofstream(base / "reach.json") << steady.dump(2);
    const auto made = fuzz::run_child({sim, "reach", "--config", (base / "reach.json").string(),
                                       "--out", (base / "reach_run").string(), "--threads", "1"},
                                      base / "reach_log.txt", 120, memory_mb * 1048576.0);
    if (made.kind != fuzz::ChildOutcome::Kind::kExited || made.code != 0) {
      std::cerr << "river_fuzzer: the base reach run failed (" << fuzz::describe(made)
                << "): " << text_of(base / "reach_log.txt") << "\n";
      return 2;
    }
  }
  const auto base_files = fuzz::leftovers(base, {});
  const std::string config_name = command + ".json";
  const nlohmann::json original = command == "reach" ? reach_config() : forecast_config();
  std::mt19937_64 rng(seed);
  fuzz::FuzzReport report;
  for (int c = 0; c < cases; ++c) {
    nlohmann::json config = original;
    std::string what;
    const int mutations = 1 + int(rng() % 3);
    for (int m = 0; m < mutations; ++m) what += " " + fuzz::mutate_json(config, rng) + ";";
    shorten(config);
    std::string text = config.dump(2);
    if (rng() % 10 == 0) {
      std::string cut;
      text = fuzz::truncated_text(text, rng, cut);
      what += " " + cut;
    }
    const fs::path dir = fs::path(work) / ("case_" + std::to_string(c));
    fs::create_directories(dir);
    std::ofstream(dir / config_name) << text;
    std::vector<std::string> run = {sim,         command,
                                    "--config",  (dir / config_name).string(),
                                    "--out",     (dir / "out").string(),
                                    "--threads", "1"};
    if (command == "forecast" && rng() % 4 != 0) run.push_back("--no-pictures");
    std::ofstream(dir / "case.txt") << what << "\n";
    const fs::path log = dir / "log.txt";
    const auto outcome = fuzz::run_child(run, log, timeout_s, memory_mb * 1048576.0);
    std::string problem = fuzz::judge(outcome, log, dir, {config_name, "case.txt"});
    // Bad input names the config (and in it the key): an exit 2 that does not leaves the user
    // to guess.
    if (problem.empty() && outcome.kind == fuzz::ChildOutcome::Kind::kExited && outcome.code == 2 &&
        text_of(log).find(config_name) == std::string::npos)
      problem = "exit 2 without naming " + config_name;
    if (problem.empty() && fuzz::leftovers(base, {}) != base_files)
      problem = "the case wrote into the base folder";
    report.add(outcome, problem, what, dir, log, keep);
    if ((c + 1) % 50 == 0)
      std::cerr << "river_fuzzer " << command << ": " << c + 1 << "/" << cases << " cases\n";
  }
  std::cout << report
                   .summary(command, {{"cases", cases},
                                      {"seed", seed},
                                      {"timeout_s", timeout_s},
                                      {"memory_mb", memory_mb}})
                   .dump(2)
            << "\n";
  return report.passed() ? 0 : 1;
}
