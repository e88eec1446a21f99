// Command fuzzer: the newer command lines as a careless or hostile user types them.
//   compare:  spill-sim compare with solver and frame lists drawn from registered and unknown
//             names, empty items, repeats, negative, decreasing, non-numeric and too late frames;
//   scene:    spill-train --scene with the generation options drawn (trajectory counts, frames,
//             splits, --vary pointers and ranges, warm-ups, --save-data);
//   teacher:  spill-train --teacher with a fitting teacher, a teacher of another model or size,
//             a damaged, missing or folder checkpoint, and student sizes drawn;
//   export:   spill-infer export from good, damaged and missing checkpoints onto new paths,
//             existing checkpoints and other files, with and without --force;
//   predict:  spill-infer predict of the tank scene with good, missing and other models'
//             checkpoints, end times, relaxation counts and scene overrides drawn;
//   reach:    spill-sim reach of a small channel raster with discharges, windows, sections,
//             CRSs, times and unknown keys drawn.
// Every case must end in exit 0, 1 or 2 (with an "error:" line when it fails), within the time
// bound, with no signal, and leave nothing but its inputs when it fails; a refused export leaves
// its target byte for byte as it was. Prints a JSON summary; exits 1 when a case misbehaved.
//
//   command_fuzzer --sim build/sim/spill-sim --train build/train/spill-train
//                  --infer build/infer/spill-infer --source . --work /tmp/fuzz --cases 120

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>

#include "tests/fuzz/child_process.h"
#include "tests/fuzz/fuzz_report.h"

namespace fs = std::filesystem;

namespace {

using Args = std::vector<std::string>;

std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

template <class T>
const T& pick(const std::vector<T>& items, std::mt19937_64& rng) {
  return items[rng() % items.size()];
}

// Mostly (7 in 10) one of `good`, else one of `bad`: cases get past the first refusal often
// enough to reach the work behind it.
std::string good_or_bad(const std::vector<std::string>& good, const std::vector<std::string>& bad,
                        std::mt19937_64& rng) {
  return rng() % 10 < 7 ? pick(good, rng) : pick(bad, rng);
}

// A comma-separated list of 1-4 items drawn from `items`, now and then with an empty item.
std::string list_of(const std::vector<std::string>& items, std::mt19937_64& rng) {
  std::string text;
  const int n = 1 + int(rng() % 4);
  for (int k = 0; k < n; ++k) text += (k ? "," : "") + pick(items, rng);
  if (rng() % 6 == 0) text.insert(rng() % (text.size() + 1), ",");
  return text;
}

// What a case runs and what it may leave when it fails.
struct Case {
  Args command;
  std::string what;
  std::set<std::string> inputs;   // case-folder entries present before it ran
  fs::path unchanged_on_failure;  // a file a refused command must not touch (empty: none)
};

struct Paths {
  std::string sim, train, infer, source;
  fs::path intact;  // the setup's scene, dataset, checkpoints
};

Case compare_case(const Paths& p, const fs::path& dir, std::mt19937_64& rng) {
  const std::vector<std::string> solvers = {"wcsph", "dfsph", "mtdf", "pbf", "iisph", "pfsph"};
  const std::vector<std::string> bad_solvers = {"sph", "", "DFSPH", "mtdf "};
  const std::vector<std::string> frames = {"1,2", "2", "1,3", "3"};
  const std::vector<std::string> bad_frames = {"0", "-1", "99", "2.5", "x", "", "2,1", "1,,2"};
  Args c = {p.sim,       "compare",
            "--scene",   (p.intact / "tank.json").string(),
            "--solvers", rng() % 10 < 7 ? list_of(solvers, rng) : list_of(bad_solvers, rng),
            "--frames",  good_or_bad(frames, bad_frames, rng),
            "--out",     (dir / "out").string(),
            "--threads", "1"};
  if (rng() % 3 == 0)
    c.insert(
        c.end(),
        {"--set", pick<std::string>(
                      {"/end_time=0.06", "/end_time=0", "/solver=x", "/output/frame_dt=-1"}, rng)});
  std::string what = "spill-sim compare --solvers " + c[5] + " --frames " + c[7];
  return {c, what, {}, {}};
}

Case scene_case(const Paths& p, const fs::path& dir, std::mt19937_64& rng) {
  Args c = {p.train,
            "--config",
            p.source + "/configs/training/gns_smoke.json",
            "--scene",
            (p.intact / "tank.json").string(),
            "--trajectories",
            good_or_bad({"3", "4"}, {"1", "0", "-2", "many"}, rng),
            "--out",
            (dir / "run").string(),
            "--threads",
            "1",
            "--set",
            "/steps=2",
            "/validate_every=2",
            "/checkpoint_every=2",
            "/validation_rollout_frames=2"};
  if (rng() % 2)
    c.insert(c.end(), {"--frames", good_or_bad({"6", "8"}, {"3", "0", "100000", "x"}, rng)});
  if (rng() % 2)
    c.insert(c.end(), {"--split", good_or_bad({"0.34/0.33/0.33", "0.5/0.5/0"},
                                              {"1/0/0", "0.5/0.5", "a/b/c", "-1/1/1"}, rng)});
  if (rng() % 2)
    c.insert(c.end(), {"--vary",
                       good_or_bad({"/fluid_blocks/0/velocity/0=0:1", "/particle_radius=0.02:0.03"},
                                   {"/end_time=0.1:0.2", "/nope=0:1",
                                    "/fluid_blocks/0/velocity/0=1:0", "fluid=0:1"},
                                   rng)});
  if (rng() % 3 == 0)
    c.insert(c.end(), {"--warm-up", good_or_bad({"0", "0.02"}, {"10", "-1"}, rng)});
  if (rng() % 3 == 0)
    c.insert(c.end(),
             {"--save-data", pick<std::string>({(dir / "saved").string(), (dir / "run").string(),
                                                (p.intact / "tank.json").string()},
                                               rng)});
  std::string what = "spill-train --scene";
  for (size_t k = 5; k < c.size(); ++k)
    if (c[k].rfind("--", 0) == 0 && c[k] != "--out" && c[k] != "--threads" && c[k] != "--set")
      what += " " + c[k] + " " + (k + 1 < c.size() ? c[k + 1] : "");
  return {c, what, {}, {}};
}

Case teacher_case(const Paths& p, const fs::path& dir, std::mt19937_64& rng) {
  // The teacher: a fitting PAGATNet, a GNS, a damaged copy, nothing, a folder.
  const int which = rng() % 2 ? 0 : int(rng() % 5);
  std::string teacher = (p.intact / "pagat" / "last.pt").string(), what = "fitting teacher";
  std::set<std::string> inputs;
  if (which == 1) {
    teacher = (p.intact / "run" / "last.pt").string(), what = "a GNS teacher";
  } else if (which == 2) {
    std::string bytes = read_bytes(teacher);
    bytes.resize(bytes.size() * (rng() % 100) / 100);
    std::ofstream(dir / "teacher.pt", std::ios::binary) << bytes;
    teacher = (dir / "teacher.pt").string(), what = "a truncated teacher";
    inputs.insert("teacher.pt");
  } else if (which == 3) {
    teacher = (dir / "missing.pt").string(), what = "a missing teacher";
  } else if (which == 4) {
    teacher = p.intact.string(), what = "a folder as teacher";
  }
  const std::string blocks = good_or_bad({"1"}, {"2", "3", "0"}, rng);
  const std::string latent = good_or_bad({"8"}, {"16", "0", "-4"}, rng);
  Args c = {p.train,
            "--config",
            p.source + "/configs/training/pagat_smoke.json",
            "--data",
            (p.intact / "data").string(),
            "--out",
            (dir / "run").string(),
            "--teacher",
            teacher,
            "--threads",
            "1",
            "--set",
            "/steps=2",
            "/validate_every=2",
            "/checkpoint_every=2",
            "/validation_rollout_frames=2",
            "/model/blocks=" + blocks,
            "/model/latent=" + latent};
  return {
      c, "spill-train --teacher (" + what + ") blocks " + blocks + " latent " + latent, inputs, {}};
}

Case export_case(const Paths& p, const fs::path& dir, std::mt19937_64& rng) {
  std::set<std::string> inputs;
  // The source: a good checkpoint, a damaged copy, a missing one.
  const int from = int(rng() % 3);
  std::string checkpoint = (p.intact / "run" / "last.pt").string(), what = "good checkpoint";
  if (from == 1) {
    std::string bytes = read_bytes(checkpoint);
    for (int k = 0; k < 8; ++k) bytes[rng() % bytes.size()] ^= char(1 + rng() % 255);
    std::ofstream(dir / "damaged.pt", std::ios::binary) << bytes;
    checkpoint = (dir / "damaged.pt").string(), what = "damaged checkpoint";
    inputs.insert("damaged.pt");
  } else if (from == 2) {
    checkpoint = (dir / "missing.pt").string(), what = "missing checkpoint";
  }
  // The target: new, an existing checkpoint, an existing text file, a folder, under a file.
  const int to = int(rng() % 5);
  fs::path target = dir / "new.pt";
  fs::path guarded;
  if (to == 1) {
    fs::copy_file(p.intact / "run" / "last.pt", dir / "other.pt");
    target = guarded = dir / "other.pt", what += " onto a checkpoint";
    inputs.insert("other.pt");
  } else if (to == 2) {
    std::ofstream(dir / "notes.txt") << "field notes\n";
    target = guarded = dir / "notes.txt", what += " onto a text file";
    inputs.insert("notes.txt");
  } else if (to == 3) {
    fs::create_directories(dir / "folder");
    target = dir / "folder", what += " onto a folder";
    inputs.insert("folder");
  } else if (to == 4) {
    std::ofstream(dir / "file") << "x";
    target = dir / "file" / "new.pt", what += " under a file";
    inputs.insert("file");
  } else {
    what += " to a new file";
  }
  Args c = {p.infer, "export", "--checkpoint", checkpoint, "--out", target.string()};
  if (rng() % 2) c.push_back("--force"), what += " --force";
  return {c, "spill-infer export: " + what, inputs, guarded};
}

Case predict_case(const Paths& p, const fs::path& dir, std::mt19937_64& rng) {
  const std::string checkpoint =
      rng() % 10 < 7 ? (p.intact / "run" / "last.pt").string()
                     : pick<std::string>({(p.intact / "pagat" / "last.pt").string(),
                                          (dir / "missing.pt").string(), p.intact.string()},
                                         rng);
  Args c = {p.infer,        "predict",
            "--checkpoint", checkpoint,
            "--scene",      (p.intact / "tank.json").string(),
            "--out",        (dir / "out").string(),
            "--threads",    "1"};
  std::string what = "spill-infer predict " + fs::path(checkpoint).filename().string();
  if (rng() % 2) {
    const std::string end = good_or_bad({"0.06", "0.1"}, {"0", "-1", "abc", "0.001"}, rng);
    c.insert(c.end(), {"--end-time", end});
    what += " --end-time " + end;
  }
  if (rng() % 3 == 0) {
    const std::string relax = good_or_bad({"0", "2"}, {"-1", "101", "abc", "1.5"}, rng);
    c.insert(c.end(), {"--relax", relax});
    what += " --relax " + relax;
  }
  if (rng() % 3 == 0) {
    const std::string set = pick<std::string>(
        {"/output/frame_dt=0.04", "/particle_radius=0.03", "/end_time=0.08", "/solver=none"}, rng);
    c.insert(c.end(), {"--set", set});
    what += " --set " + set;
  }
  return {c, what, {}, {}};
}

Case reach_case(const Paths& p, const fs::path& dir, std::mt19937_64& rng) {
  Args c = {p.sim,       "reach",
            "--config",  (p.intact / "reach.json").string(),
            "--out",     (dir / "out").string(),
            "--threads", "1",
            "--set"};
  const std::vector<std::string> good = {"/end_time=60", "/inflows/0/discharge/value=0.5",
                                         "/terrain/coarsen=2", "/output_every=20",
                                         "/terrain/manning=0.05"};
  const std::vector<std::string> bad = {"/end_time=-1",
                                        "/inflows/0/discharge/value=-3",
                                        "/terrain/window=[0,0,1,1]",
                                        "/terrain/crs=EPSG:4326",
                                        "/terrain/crs=nonsense",
                                        "/terrain/file=missing.tif",
                                        "/inflows/0/section/from=-100",
                                        "/outflows/0/kind=weir",
                                        "/cfl=0.9",
                                        "/terrain/coarsen=0",
                                        "/terrain/manning=abc",
                                        "/unknown_key=1"};
  std::string what = "spill-sim reach --set";
  const int n = 1 + int(rng() % 3);
  for (int k = 0; k < n; ++k) {
    c.push_back(good_or_bad(good, bad, rng));
    what += " " + c.back();
  }
  return {c, what, {}, {}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Command fuzzer for compare, spill-train --scene and --teacher, export, predict and reach"};
  Paths p;
  std::string work;
  int cases = 120;
  std::uint64_t seed = 1;
  double timeout_s = 120, memory_mb = 4096;
  bool keep = false;
  app.add_option("--sim", p.sim, "spill-sim executable")->required();
  app.add_option("--train", p.train, "spill-train executable")->required();
  app.add_option("--infer", p.infer, "spill-infer executable")->required();
  app.add_option("--source", p.source, "source folder (configs/)")->required();
  app.add_option("--work", work, "scratch folder (emptied)")->required();
  app.add_option("--cases", cases, "number of cases");
  app.add_option("--seed", seed, "random seed");
  app.add_option("--timeout", timeout_s, "seconds after which a case counts as hung");
  app.add_option("--memory-mb", memory_mb, "memory limit of each run (RLIMIT_DATA)");
  app.add_flag("--keep", keep, "keep every case's folder, not only failed ones");
  CLI11_PARSE(app, argc, argv);

  // The intact inputs: a small tank, its three-trajectory dataset, a briefly trained GNS and a
  // PAGATNet teacher of the smoke config (which a one-block student of width 8 fits).
  p.intact = fs::path(work) / "intact";
  fs::remove_all(work);
  fs::create_directories(p.intact);
  std::ofstream(p.intact / "tank.json") << R"({
    "name": "tank", "particle_radius": 0.02, "end_time": 0.16, "output": {"frame_dt": 0.02},
    "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2], "velocity": [0, 0, 0]}]})";
  // A channel 200 m long falling to the west between banks, as an ESRI ASCII grid (no CRS in it:
  // the config names one), and its reach config.
  {
    std::ofstream asc(p.intact / "channel.asc");
    asc << "ncols 20\nnrows 6\nxllcorner 1771000\nyllcorner 5472000\ncellsize 10\n";
    for (int row = 0; row < 6; ++row) {
      for (int i = 0; i < 20; ++i)
        asc << (0.001 * (10 * i + 5) + ((row == 0 || row == 5) ? 2.0 : 0.0)) << " ";
      asc << "\n";
    }
  }
  std::ofstream(p.intact / "reach.json") << R"({
    "name": "channel", "terrain": {"file": "channel.asc", "crs": "EPSG:2193"},
    "inflows": [{"section": {"name": "up", "side": "east", "from": 5472010, "to": 5472050},
                 "discharge": {"value": 2}}],
    "outflows": [{"section": {"name": "down", "side": "west", "from": 5472010, "to": 5472050},
                  "kind": "normal_depth", "slope": 0.001}],
    "end_time": 120, "output_every": 60})";
  const double limit = memory_mb * 1048576.0;
  const Args steps = {"--threads",        "1", "--set", "/steps=4", "/checkpoint_every=4",
                      "/validate_every=4"};
  auto with = [](Args a, const Args& more) {
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  for (const Args& setup :
       {Args{p.sim, "generate", "--scene", (p.intact / "tank.json").string(), "--trajectories", "3",
             "--split", "0.34/0.33/0.33", "--out", (p.intact / "data").string(), "--threads", "1"},
        with({p.train, "--config", p.source + "/configs/training/gns_smoke.json", "--data",
              (p.intact / "data").string(), "--out", (p.intact / "run").string()},
             steps),
        with({p.train, "--config", p.source + "/configs/training/pagat_smoke.json", "--data",
              (p.intact / "data").string(), "--out", (p.intact / "pagat").string()},
             steps)}) {
    const auto o = fuzz::run_child(setup, p.intact / "setup.txt", 600, limit);
    if (o.kind != fuzz::ChildOutcome::Kind::kExited || o.code != 0) {
      std::cerr << "command_fuzzer: setup failed (" << fuzz::describe(o) << "):\n"
                << read_bytes(p.intact / "setup.txt");
      return 2;
    }
  }
  const std::string intact_before = read_bytes(p.intact / "run" / "last.pt");

  std::mt19937_64 rng(seed);
  fuzz::FuzzReport report;
  for (int c = 0; c < cases; ++c) {
    const fs::path dir = fs::path(work) / ("case_" + std::to_string(c));
    fs::create_directories(dir);
    const int kind = c % 6;  // each surface in turn
    Case k = kind == 0   ? compare_case(p, dir, rng)
             : kind == 1 ? scene_case(p, dir, rng)
             : kind == 2 ? teacher_case(p, dir, rng)
             : kind == 3 ? export_case(p, dir, rng)
             : kind == 4 ? predict_case(p, dir, rng)
                         : reach_case(p, dir, rng);
    const std::string guarded_before =
        k.unchanged_on_failure.empty() ? "" : read_bytes(k.unchanged_on_failure);
    std::ofstream(dir / "case.txt") << k.what << "\n";  // what was done, for a look
    k.inputs.insert("case.txt");
    const fs::path log = dir / "log.txt";
    const auto outcome = fuzz::run_child(k.command, log, timeout_s, limit);
    std::string problem = fuzz::judge(outcome, log, dir, k.inputs);
    if (problem.empty() && outcome.code != 0 && !k.unchanged_on_failure.empty() &&
        read_bytes(k.unchanged_on_failure) != guarded_before)
      problem = fuzz::describe(outcome) + " but changed " + k.unchanged_on_failure.string();
    if (problem.empty() && read_bytes(p.intact / "run" / "last.pt") != intact_before)
      problem = "changed the intact checkpoint";
    report.add(outcome, problem, k.what, dir, log, keep);
    if ((c + 1) % 40 == 0) std::cerr << "command_fuzzer: " << c + 1 << "/" << cases << " cases\n";
  }
  std::cout << report
                   .summary("command", {{"cases", cases},
                                        {"seed", seed},
                                        {"timeout_s", timeout_s},
                                        {"memory_mb", memory_mb}})
                   .dump(2)
            << "\n";
  return report.passed() ? 0 : 1;
}
