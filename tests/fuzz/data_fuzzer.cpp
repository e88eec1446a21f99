// Dataset and checkpoint fuzzer: damages a small generated dataset or a trained checkpoint as a
// disk, a copy or a careless edit would (truncated, bytes flipped, a dataset or a tensor of
// another shape or type, NaN positions, metadata.json mutated) and runs spill-infer eval,
// spill-infer rollout, spill-train or spill-train --resume on it. Every case must end in exit 0,
// 1 or 2 with a message, within the time bound, with no signal, and leave no output behind when
// it fails. Prints a JSON summary; exits 1 when a case misbehaved (its folder is kept).
//
//   data_fuzzer --sim build/sim/spill-sim --train build/train/spill-train
//               --infer build/infer/spill-infer --source . --work /tmp/fuzz --cases 200

#include <hdf5.h>
#include <torch/torch.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>

#include "tests/fuzz/child_process.h"
#include "tests/fuzz/fuzz_report.h"
#include "tests/fuzz/json_mutation.h"

namespace fs = std::filesystem;

namespace {

std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_bytes(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
}

std::string flip_bytes(const fs::path& file, std::mt19937_64& rng) {
  std::string bytes = read_bytes(file);
  if (bytes.empty()) return "empty file";
  const int flips = 1 + int(rng() % 16);
  for (int k = 0; k < flips; ++k) bytes[rng() % bytes.size()] ^= char(1 + rng() % 255);
  write_bytes(file, bytes);
  return "flip " + std::to_string(flips) + " bytes of " + file.filename().string();
}

std::string truncate_file(const fs::path& file, std::mt19937_64& rng) {
  std::string bytes = read_bytes(file);
  const size_t at = bytes.empty() ? 0 : rng() % bytes.size();
  write_bytes(file, bytes.substr(0, at));
  return "truncate " + file.filename().string() + " to " + std::to_string(at) + " of " +
         std::to_string(bytes.size()) + " bytes";
}

// Replaces one dataset of the first trajectory group by one of another shape or type, or fills
// its floats with NaN.
std::string reshape_hdf5(const fs::path& file, std::mt19937_64& rng) {
  const char* names[] = {"position", "particle_type",     "active",         "velocity",
                         "time",     "boundary_position", "volume_fraction"};
  const std::string name = names[rng() % 7];
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (f < 0) return "cannot open " + file.string();
  std::string what = file.filename().string() + ":/00000/" + name;
  const hid_t g = H5Gopen2(f, "00000", H5P_DEFAULT);
  if (g >= 0 && H5Lexists(g, name.c_str(), H5P_DEFAULT) > 0) {
    const hid_t d = H5Dopen2(g, name.c_str(), H5P_DEFAULT);
    const hid_t space = H5Dget_space(d);
    hsize_t dims[8] = {0};
    int rank = H5Sget_simple_extent_ndims(space);
    H5Sget_simple_extent_dims(space, dims, nullptr);
    H5Sclose(space);
    H5Dclose(d);
    hid_t type = H5T_NATIVE_FLOAT;
    double fill = 0;
    switch (rng() % 4) {
      case 0:  // one fewer along the last axis
        dims[rank - 1] = dims[rank - 1] > 1 ? dims[rank - 1] - 1 : 2;
        what += " reshaped";
        break;
      case 1:  // an extra axis
        dims[rank] = 2;
        rank += 1;
        what += " given an extra axis";
        break;
      case 2:
        type = rng() % 2 ? H5T_NATIVE_DOUBLE : H5T_NATIVE_INT8;
        what += " retyped";
        break;
      default:
        fill = std::nan("");
        what += " filled with NaN";
        break;
    }
    H5Ldelete(g, name.c_str(), H5P_DEFAULT);
    const hid_t new_space = H5Screate_simple(rank, dims, nullptr);
    hsize_t count = 1;
    for (int k = 0; k < rank; ++k) count *= dims[k];
    std::vector<double> values(count, fill);
    const hid_t created =
        H5Dcreate2(g, name.c_str(), type, new_space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(created, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Dclose(created);
    H5Sclose(new_space);
  } else {
    what += " (absent: unchanged)";
  }
  if (g >= 0) H5Gclose(g);
  H5Fclose(f);
  return what;
}

// Rewrites the checkpoint with one tensor of another shape or type (and without the optimizer
// state, which cannot be copied key by key).
std::string reshape_checkpoint(const fs::path& file, std::mt19937_64& rng) {
  torch::serialize::InputArchive in;
  in.load_from(file.string());
  torch::serialize::OutputArchive out;
  const auto keys = in.keys();
  std::vector<std::string> tensors;
  std::map<std::string, torch::Tensor> values;
  for (const auto& key : keys) {
    torch::Tensor t;
    if (in.try_read(key, t)) values[key] = t, tensors.push_back(key);
  }
  const std::string victim = tensors[rng() % tensors.size()];
  torch::Tensor& t = values[victim];
  std::string what = "last.pt:" + victim;
  if (rng() % 2 && t.numel() > 1) {
    t = t.flatten().slice(0, 0, t.numel() - 1).clone();
    what += " reshaped to [" + std::to_string(t.numel()) + "]";
  } else {
    t = t.to(t.is_floating_point() ? torch::kInt32 : torch::kFloat64);
    what += " retyped";
  }
  for (const auto& [key, value] : values) out.write(key, value);
  out.save_to(file.string());
  return what;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Dataset and checkpoint fuzzer for spill-train and spill-infer"};
  std::string sim, train, infer, source, work;
  int cases = 200;
  std::uint64_t seed = 1;
  double timeout_s = 60, memory_mb = 4096;
  bool keep = false;
  app.add_option("--sim", sim, "spill-sim executable")->required();
  app.add_option("--train", train, "spill-train executable")->required();
  app.add_option("--infer", infer, "spill-infer executable")->required();
  app.add_option("--source", source, "source folder (configs/)")->required();
  app.add_option("--work", work, "scratch folder (emptied)")->required();
  app.add_option("--cases", cases, "number of cases");
  app.add_option("--seed", seed, "random seed");
  app.add_option("--timeout", timeout_s, "seconds after which a case counts as hung");
  app.add_option("--memory-mb", memory_mb, "memory limit of each run (RLIMIT_DATA)");
  app.add_flag("--keep", keep, "keep every case's folder, not only failed ones");
  CLI11_PARSE(app, argc, argv);
  torch::set_num_threads(1);

  // The intact inputs: a three-trajectory dataset of a small tank and a briefly trained model.
  const fs::path base = fs::path(work) / "intact";
  fs::remove_all(work);
  fs::create_directories(base);
  std::ofstream(base / "tank.json") << R"({
    "name": "tank", "particle_radius": 0.02, "end_time": 0.3, "output": {"frame_dt": 0.02},
    "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}]})";
  const std::string training_config = source + "/configs/training/gns_smoke.json";
  const double limit = memory_mb * 1048576.0;
  for (const auto& setup :
       {std::vector<std::string>{sim, "generate", "--scene", (base / "tank.json").string(),
                                 "--trajectories", "3", "--split", "0.34/0.33/0.33", "--frames",
                                 "12", "--out", (base / "data").string(), "--threads", "1"},
        std::vector<std::string>{train, "--config", training_config, "--data",
                                 (base / "data").string(), "--out", (base / "run").string(),
                                 "--threads", "1", "--set", "/steps=4", "--set",
                                 "/checkpoint_every=4", "--set", "/validate_every=4"}}) {
    const auto o = fuzz::run_child(setup, base / "setup.txt", 600, limit);
    if (o.kind != fuzz::ChildOutcome::Kind::kExited || o.code != 0) {
      std::cerr << "data_fuzzer: setup failed (" << fuzz::describe(o) << "):\n"
                << read_bytes(base / "setup.txt");
      return 2;
    }
  }

  std::mt19937_64 rng(seed);
  fuzz::FuzzReport report;
  for (int c = 0; c < cases; ++c) {
    const fs::path dir = fs::path(work) / ("case_" + std::to_string(c));
    fs::create_directories(dir);
    fs::copy(base / "data", dir / "data", fs::copy_options::recursive);
    fs::remove_all(dir / "data" / "parts");
    fs::copy(base / "run", dir / "run", fs::copy_options::recursive);
    const fs::path checkpoint = dir / "run" / "last.pt";
    // What to damage, and a command that reads it.
    const int target = int(rng() % 5);  // metadata, train, valid, test split, checkpoint
    const char* files[] = {"metadata.json", "train.h5", "valid.h5", "test.h5"};
    std::string what;
    const fs::path damaged = target < 4 ? dir / "data" / files[target] : checkpoint;
    const int how = int(rng() % 3);
    if (target == 0) {
      nlohmann::json j;
      std::ifstream(damaged) >> j;
      if (how == 0) {
        std::string text = j.dump(2);
        write_bytes(damaged, fuzz::truncated_text(text, rng, what));
        what = "metadata.json: " + what;
      } else {
        what = "metadata.json: " + fuzz::mutate_json(j, rng);
        write_bytes(damaged, j.dump(2));
      }
    } else if (how == 0) {
      what = truncate_file(damaged, rng);
    } else if (how == 1) {
      what = flip_bytes(damaged, rng);
    } else {
      what = target < 4 ? reshape_hdf5(damaged, rng) : reshape_checkpoint(damaged, rng);
    }
    const std::string data = (dir / "data").string(), out = (dir / "out").string();
    const std::string split = target == 3 ? "test" : "valid";
    std::vector<std::string> command;
    const int kind = target == 1 ? 2 : int(rng() % 4);
    if (kind == 0)
      command = {infer,    "eval", "--checkpoint", checkpoint.string(),
                 "--data", data,   "--split",      split,
                 "--out",  out,    "--threads",    "1"};
    else if (kind == 1)
      command = {infer,       "rollout", "--checkpoint", checkpoint.string(),
                 "--data",    data,      "--split",      split,
                 "--frames",  "5",       "--out",        out,
                 "--threads", "1"};
    else if (kind == 2)
      command = {train,   training_config,    "--data", data,    "--out",
                 out,     "--threads",        "1",      "--set", "/steps=2",
                 "--set", "/validate_every=2"};
    else
      command = {train,      training_config, "--data", data,    "--out",   (dir / "run").string(),
                 "--resume", "--threads",     "1",      "--set", "/steps=6"};
    if (kind >= 2) command.insert(command.begin() + 1, "--config");
    const char* labels[] = {"spill-infer eval", "spill-infer rollout", "spill-train",
                            "spill-train --resume"};
    what += "; " + std::string(labels[kind]);
    std::ofstream(dir / "case.txt") << what << "\n";  // what was done, for a look
    const fs::path log = dir / "log.txt";
    const auto outcome = fuzz::run_child(command, log, timeout_s, limit);
    const std::string problem = fuzz::judge(outcome, log, dir, {"data", "run", "case.txt"});
    report.add(outcome, problem, what, dir, log, keep);
    if ((c + 1) % 50 == 0) std::cerr << "data_fuzzer: " << c + 1 << "/" << cases << " cases\n";
  }
  std::cout << report
                   .summary("data", {{"cases", cases},
                                     {"seed", seed},
                                     {"timeout_s", timeout_s},
                                     {"memory_mb", memory_mb}})
                   .dump(2)
            << "\n";
  return report.passed() ? 0 : 1;
}
