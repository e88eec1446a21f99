// Scene fuzzer: mutates the shipped scenes as a careless or hostile user would (keys deleted, signs
// flipped, numbers scaled by 1e-9 .. 1e9, types swapped, files truncated) and runs `spill-sim run`
// on each. Every case must end in exit 0, 1 or 2 (with a message), within the time bound, with
// no signal, and leave nothing beside the scene when it fails. Prints a JSON summary; exits 1
// when a case misbehaved (its folder is kept).
//
//   scene_fuzzer --sim build/sim/spill-sim --scenes configs/scenes --work /tmp/fuzz --cases 300

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>

#include "tests/fuzz/child_process.h"
#include "tests/fuzz/fuzz_report.h"
#include "tests/fuzz/json_mutation.h"

namespace fs = std::filesystem;

namespace {

// Runs are kept to two frames so a healthy case is quick and a slow one is a hang; an end time
// that the scene check refuses (over 1e7 frames, not a number) is left for it to refuse.
void shorten(nlohmann::json& scene) {
  if (!scene.is_object() || !scene.contains("end_time") || !scene["end_time"].is_number()) return;
  double frame_dt = 0.05;
  if (scene.contains("output") && scene["output"].is_object() &&
      scene["output"].contains("frame_dt") && scene["output"]["frame_dt"].is_number() &&
      scene["output"]["frame_dt"].get<double>() > 0)
    frame_dt = scene["output"]["frame_dt"].get<double>();
  const double end = scene["end_time"].get<double>();
  if (end > 0 && end / frame_dt <= 1e7) scene["end_time"] = std::min(end, 2 * frame_dt);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Scene fuzzer for spill-sim run"};
  std::string sim, scenes, work;
  int cases = 300;
  std::uint64_t seed = 1;
  double timeout_s = 60, memory_mb = 1024;
  app.add_option("--sim", sim, "spill-sim executable")->required();
  app.add_option("--scenes", scenes, "folder of scenes to mutate")->required();
  app.add_option("--work", work, "scratch folder (emptied)")->required();
  app.add_option("--cases", cases, "number of cases");
  app.add_option("--seed", seed, "random seed");
  app.add_option("--timeout", timeout_s, "seconds after which a case counts as hung");
  app.add_option("--memory-mb", memory_mb, "memory limit of each run (RLIMIT_DATA)");
  bool keep = false;
  app.add_flag("--keep", keep, "keep every case's folder (scene and log), not only failed ones");
  CLI11_PARSE(app, argc, argv);

  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(scenes))
    if (e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    std::cerr << "scene_fuzzer: no scenes in " << scenes << "\n";
    return 2;
  }
  fs::remove_all(work);
  fs::create_directories(work);
  std::mt19937_64 rng(seed);
  fuzz::FuzzReport report;
  for (int c = 0; c < cases; ++c) {
    const fs::path source = files[rng() % files.size()];
    nlohmann::json scene;
    std::ifstream(source) >> scene;
    std::string what = source.filename().string() + ":";
    const int mutations = 1 + int(rng() % 3);
    for (int m = 0; m < mutations; ++m) what += " " + fuzz::mutate_json(scene, rng) + ";";
    shorten(scene);
    std::string text = scene.dump(2);
    if (rng() % 10 == 0) {
      std::string cut;
      text = fuzz::truncated_text(text, rng, cut);
      what += " " + cut;
    }
    const fs::path dir = fs::path(work) / ("case_" + std::to_string(c));
    fs::create_directories(dir);
    std::ofstream(dir / "scene.json") << text;
    std::vector<std::string> command = {sim,         "run",
                                        "--scene",   (dir / "scene.json").string(),
                                        "--out",     (dir / "out").string(),
                                        "--threads", "1"};
    if (rng() % 4 == 0) command.push_back("--png");
    std::ofstream(dir / "case.txt") << what << "\n";  // what was done, for a look
    const fs::path log = dir / "log.txt";
    const auto outcome = fuzz::run_child(command, log, timeout_s, memory_mb * 1048576.0);
    const std::string problem = fuzz::judge(outcome, log, dir, {"scene.json", "case.txt"});
    report.add(outcome, problem, what, dir, log, keep);
    if ((c + 1) % 50 == 0) std::cerr << "scene_fuzzer: " << c + 1 << "/" << cases << " cases\n";
  }
  std::cout << report
                   .summary("scene", {{"cases", cases},
                                      {"seed", seed},
                                      {"timeout_s", timeout_s},
                                      {"memory_mb", memory_mb},
                                      {"scenes", scenes}})
                   .dump(2)
            << "\n";
  return report.passed() ? 0 : 1;
}
