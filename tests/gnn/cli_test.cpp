// spill-train and spill-infer as a user runs them: outputs, exit codes and errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gnn/models/graph_model.h"
#include "tests/common/file_size_limit.h"
#include "tests/gnn/small_models.h"
#include "tests/gnn/tiny_dataset.h"

namespace fs = std::filesystem;

namespace {
int run(const std::string& command) {
  const int status = std::system((command + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
}  // namespace

TEST(Cli, TrainRollOutAndEvaluateOnATinyDataset) {
  const fs::path dir = fs::temp_directory_path() / ("gnn_cli_" + std::to_string(getpid()));
  fs::remove_all(dir);
  tiny::write(dir / "data");
  const std::string data = (dir / "data").string(), run_dir = (dir / "run").string();
  const std::string train = std::string(SPILL_TRAIN_EXE) + " --config " + SPILL_SOURCE_DIR +
                            "/configs/training/gns_smoke.json --data " + data + " --threads 1";
  ASSERT_EQ(run(train + " --out " + run_dir + " --set /steps=30"), 0);
  std::ifstream log(run_dir + "/log.csv");
  std::string header;
  std::getline(log, header);
  EXPECT_NE(header.find("loss"), std::string::npos);
  ASSERT_TRUE(fs::exists(run_dir + "/last.pt"));

  const std::string infer = std::string(SPILL_INFER_EXE);
  // The tiny dataset is drawn, not simulated: it has no scene to roll out standalone from, so
  // its rollouts replay the recorded sources, and without the option eval says so.
  const std::string standalone =
      " --checkpoint " + run_dir + "/last.pt --data " + data + " --threads 1";
  EXPECT_EQ(run("(" + infer + " eval" + standalone + " --out " + (dir / "standalone").string() +
                " 2> " + (dir / "standalone.log").string() + ")"),
            2);
  std::ifstream standalone_log(dir / "standalone.log");
  const std::string said((std::istreambuf_iterator<char>(standalone_log)), {});
  EXPECT_NE(said.find("--replay-recorded-sources"), std::string::npos) << said;
  EXPECT_FALSE(fs::exists(dir / "standalone"));
  const std::string ckpt = standalone + " --replay-recorded-sources";
  ASSERT_EQ(run(infer + " eval" + ckpt + " --out " + (dir / "eval").string()), 0);
  nlohmann::json eval;
  std::ifstream(dir / "eval/eval.json") >> eval;
  EXPECT_TRUE(eval.contains("one_step_mse"));
  for (const char* h : {"1", "5", "10", "all"}) EXPECT_TRUE(eval["rollout_mse"].contains(h)) << h;
  EXPECT_TRUE(fs::exists(dir / "eval/error_vs_horizon.svg"));

  // A trailing slash names the folder itself; a second rollout replaces the first.
  for (int repeat = 0; repeat < 2; ++repeat)
    ASSERT_EQ(run(infer + " rollout" + ckpt + " --trajectory 0 --from 5 --frames 10 --out " +
                  (dir / "rollout").string() + "/"),
              0);
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".rollout"), std::string::npos) << e.path();
  // The working folder, or a folder holding the data, is never an output folder.
  EXPECT_EQ(run("cd " + data + " && " + infer + " rollout" + ckpt + " --out ."), 2);
  EXPECT_EQ(run(infer + " eval" + ckpt + " --out " + dir.string()), 2);
  EXPECT_TRUE(fs::exists(data + "/metadata.json"));
  EXPECT_TRUE(fs::exists(dir / "rollout/rollout.h5"));
  EXPECT_TRUE(fs::exists(dir / "rollout/frames/compare_0015.png"));
  nlohmann::json timing;
  std::ifstream(dir / "rollout/timing.json") >> timing;
  EXPECT_GT(timing["wall_s_per_frame"].get<double>(), 0);

  // Bad input: a non-zero exit and no output.
  // Bad input exits 2 from every executable (one exit-code policy, common/exit_codes.h).
  std::ofstream(dir / "bad.pt") << "garbage";
  EXPECT_EQ(run(infer + " eval --checkpoint " + (dir / "bad.pt").string() + " --data " + data +
                " --out " + (dir / "bad_eval").string()),
            2);
  EXPECT_FALSE(fs::exists(dir / "bad_eval"));
  EXPECT_EQ(run(train + " --out " + (dir / "bad_run").string() + " --set /modle=1"), 2);
  EXPECT_EQ(run(infer + " rollout" + ckpt + " --device tpu --out " + (dir / "bad_device").string()),
            2);
  EXPECT_FALSE(fs::exists(dir / "bad_run"));
  EXPECT_EQ(run(infer + " rollout" + ckpt + " --trajectory 0 --from 5 --frames 500 --out " +
                (dir / "bad_rollout").string()),
            2);
  EXPECT_FALSE(fs::exists(dir / "bad_rollout"));
  // Training into a run without --resume, or into an --out that cannot be a folder, exits 2
  // naming --out (they were exit 1 and a raw "filesystem error"); the run is untouched.
  const auto trained = fs::last_write_time(run_dir + "/last.pt");
  EXPECT_EQ(run(train + " --out " + run_dir), 2);
  EXPECT_EQ(fs::last_write_time(run_dir + "/last.pt"), trained);
  EXPECT_EQ(run(train + " --out " + data + "/metadata.json/run"), 2);
  // --relax is a whole number up to 100 (a billion ran for minutes with no output).
  for (const char* relax : {"1000000000", "-1", "abc", "2.5"})
    EXPECT_EQ(
        run(infer + " eval" + ckpt + " --relax " + relax + " --out " + (dir / "relaxed").string()),
        2)
        << relax;
  EXPECT_FALSE(fs::exists(dir / "relaxed"));
  // Resuming with fewer steps than were trained did nothing and exited 0 without a word.
  EXPECT_EQ(run(train + " --out " + run_dir + " --resume --set /steps=10"), 2);
  EXPECT_EQ(fs::last_write_time(run_dir + "/last.pt"), trained);
  // A teacher that does not fit the student (the shipped river teacher, graph radius 0.075, for
  // the smoke config's 0.1) is bad input, exit 2, and nothing is written.
  EXPECT_EQ(
      run(std::string(SPILL_TRAIN_EXE) + " --config " + SPILL_SOURCE_DIR +
          "/configs/training/pagat_smoke.json --data " + data + " --threads 1 --teacher " +
          SPILL_SOURCE_DIR + "/docs/results/pagat/teacher.pt --out " + (dir / "misfit").string()),
      2);
  EXPECT_FALSE(fs::exists(dir / "misfit"));

  // A validation split too short for a window (it crashed at the first validation) and a test
  // split whose fluid is never present (it scored perfectly) are refused, exit 2.
  tiny::rewrite_split(dir / "data", "valid", 5, false);
  EXPECT_EQ(run(train + " --out " + (dir / "short_valid").string() + " --set /steps=30"), 2);
  EXPECT_FALSE(fs::exists(dir / "short_valid" / "last.pt"));
  tiny::rewrite_split(dir / "data", "test", 20, true);
  EXPECT_EQ(run(infer + " eval" + ckpt + " --out " + (dir / "empty_eval").string()), 2);
  EXPECT_FALSE(fs::exists(dir / "empty_eval"));
  fs::remove_all(dir);
}

// spill-infer compare: every registered model (the registry enumerated: each trained by its
// configs/training/<model>_smoke.json for 20 steps) and the constant-velocity floor rolled out
// from the same frames of the same trajectories, one row each; bad input exits 2 with nothing
// written.
TEST(Cli, CompareWritesARowPerModelAndTheFloor) {
  const fs::path dir = fs::temp_directory_path() / ("gnn_compare_" + std::to_string(getpid()));
  fs::remove_all(dir);
  tiny::write(dir / "data");
  const std::string data = (dir / "data").string();
  std::vector<std::string> names, untrainable;
  std::string checkpoints = " --checkpoints";
  for (const std::string& model : gnn::model_names()) {
    if (gnn::make_model(small_models::config(model), "test")->parameters().empty()) {
      untrainable.push_back(model);
      continue;
    }
    const std::string smoke =
        std::string(SPILL_SOURCE_DIR) + "/configs/training/" + model + "_smoke.json";
    ASSERT_TRUE(fs::exists(smoke)) << model << " is registered but has no smoke config " << smoke;
    ASSERT_EQ(run(std::string(SPILL_TRAIN_EXE) + " --config " + smoke + " --data " + data +
                  " --threads 1 --set /steps=20 --out " + (dir / model).string()),
              0)
        << model;
    names.push_back(model);
    checkpoints += " " + (dir / model / "last.pt").string();
  }
  // A model without parameters is not trained: the floor is compared by --constant-velocity; any
  // other would need a row of its own here.
  ASSERT_EQ(untrainable, std::vector<std::string>{"constant_velocity"});
  names.push_back("constant_velocity");
  const std::string compare = std::string(SPILL_INFER_EXE) + " compare --data " + data +
                              " --threads 1 --from 5 --frames 8 --replay-recorded-sources";
  ASSERT_EQ(run(compare + checkpoints + " --constant-velocity --out " + (dir / "out").string()), 0);
  nlohmann::json result;
  std::ifstream(dir / "out/comparison.json") >> result;
  ASSERT_EQ(result["models"].size(), names.size());
  for (size_t k = 0; k < names.size(); ++k) {
    const auto& row = result["models"][k];
    EXPECT_EQ(row["name"], names[k]);
    EXPECT_EQ(row["model"], names[k]);
    for (const char* key :
         {"one_step_mse", "rollout_mse_5", "rollout_mse_all", "mmd", "kinetic_energy_error",
          "seconds_per_frame", "seconds_per_simulated_second", "flops_per_particle"})
      EXPECT_TRUE(row[key].is_number()) << names[k] << " " << key;
    // 8 frames: no 10-frame figures, and the tiny dataset's scene has no river to measure.
    EXPECT_TRUE(row["rollout_mse_10"].is_null());
    EXPECT_TRUE(row["front_distance_error_m"].is_null());
    EXPECT_TRUE(row["spread"].contains("rollout_mse_5"));
    EXPECT_EQ(row["by_frame"]["rollout_mse"].size(), 8u);
    EXPECT_EQ(row["by_frame"]["rollout_mse"][4], row["rollout_mse_5"]);
  }
  EXPECT_EQ(result["models"].back()["params"], 0);
  EXPECT_EQ(result["models"].back()["flops_per_particle"], 0.0);
  for (size_t k = 0; k + 1 < names.size(); ++k)
    EXPECT_GT(result["models"][k]["params"].get<int64_t>(), 0) << names[k];
  EXPECT_EQ(result["trajectories"].size(), 1u);
  EXPECT_TRUE(fs::exists(dir / "out/comparison.md"));
  EXPECT_TRUE(fs::exists(dir / "out/comparison.png"));
  {
    // report.html: the models side by side, one row each, in one file with nothing fetched.
    std::ifstream in(dir / "out/report.html");
    const std::string page((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t table = page.find("<table id=\"models\">");
    ASSERT_NE(table, std::string::npos);
    const std::string models = page.substr(table, page.find("</table>", table) - table);
    for (const auto& name : names)
      EXPECT_NE(models.find("<tr><td>" + name + "</td>"), std::string::npos) << name;
    EXPECT_NE(page.find("data:image/png;base64,"), std::string::npos);  // comparison.png
    EXPECT_EQ(page.find(" src=\"http"), std::string::npos);
  }
  EXPECT_FALSE(fs::exists(dir / "out/teacher_student.md"));  // neither a teacher nor a student
  EXPECT_EQ(run(compare + " --out " + (dir / "nothing").string()), 2);  // no model at all
  EXPECT_EQ(run(compare + " --checkpoints " + (dir / "none.pt").string() + " --out " +
                (dir / "missing").string()),
            2);
  std::ofstream(dir / "bad.pt") << "garbage";
  EXPECT_EQ(run(compare + " --checkpoints " + (dir / "bad.pt").string() + " --out " +
                (dir / "bad").string()),
            2);
  // Jittered members are standalone rollouts: a replayed recording has none.
  EXPECT_EQ(run(compare + checkpoints + " --members 2 --out " + (dir / "members").string()), 2);
  for (const char* out : {"nothing", "missing", "bad", "members"})
    EXPECT_FALSE(fs::exists(dir / out)) << out;

  // spill-infer export: a weights-only copy rolls out exactly as the original does, is less than
  // half its size (Adam keeps two moments per weight), and cannot be resumed from.
  const std::string exported = (dir / "gns_weights.pt").string();
  const std::string export_cmd = std::string(SPILL_INFER_EXE) + " export --checkpoint ";
  ASSERT_EQ(run(export_cmd + (dir / "gns/last.pt").string() + " --out " + exported), 0);
  EXPECT_LT(fs::file_size(exported), fs::file_size(dir / "gns/last.pt") / 2);
  ASSERT_EQ(run(compare + " --checkpoints " + (dir / "gns/last.pt").string() + " " + exported +
                " --out " + (dir / "exported").string()),
            0);
  nlohmann::json again;
  std::ifstream(dir / "exported/comparison.json") >> again;
  ASSERT_EQ(again["models"].size(), 2u);
  EXPECT_EQ(again["models"][1]["name"], "gns_weights");
  for (const char* key : {"one_step_mse", "rollout_mse_5", "rollout_mse_all"})
    EXPECT_EQ(again["models"][1][key], again["models"][0][key]) << key;
  fs::copy(dir / "gns", dir / "gns_resume", fs::copy_options::recursive);
  fs::copy_file(exported, dir / "gns_resume/last.pt", fs::copy_options::overwrite_existing);
  EXPECT_EQ(run(std::string(SPILL_TRAIN_EXE) + " --config " + SPILL_SOURCE_DIR +
                "/configs/training/gns_smoke.json --data " + data +
                " --threads 1 --set /steps=30 --resume --out " + (dir / "gns_resume").string()),
            2);
  EXPECT_EQ(run(export_cmd + exported + " --out " + exported), 2);  // not onto itself
  // An existing --out is refused: over another run's last.pt the copy would silently make that
  // run unresumable. --force replaces a checkpoint, never a file that is not one.
  const fs::path other_run = dir / "other_run_last.pt", notes = dir / "notes.txt";
  fs::copy_file(dir / "gns/last.pt", other_run);
  const auto full_size = fs::file_size(other_run);
  const std::string from_gns = export_cmd + (dir / "gns/last.pt").string() + " --out ";
  EXPECT_EQ(run(from_gns + other_run.string()), 2);
  EXPECT_EQ(fs::file_size(other_run), full_size);
  std::ofstream(notes) << "boom positions";
  EXPECT_EQ(run(from_gns + notes.string() + " --force"), 2);
  std::string text;
  std::getline(std::ifstream(notes), text);
  EXPECT_EQ(text, "boom positions");
  EXPECT_EQ(run(from_gns + dir.string() + " --force"), 2);  // a folder is not a checkpoint
  ASSERT_EQ(run(from_gns + other_run.string() + " --force"), 0);
  EXPECT_LT(fs::file_size(other_run), full_size / 2);  // now the weights-only copy
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_NE(entry.path().extension(), ".tmp") << "left behind: " << entry.path();
  EXPECT_EQ(run(export_cmd + (dir / "none.pt").string() + " --out " + exported), 2);
  fs::remove_all(dir);
}

// A full disk (files limited in size): training, rollout and evaluation exit 1 naming the file,
// with no signal (LibTorch's checkpoint writer aborted; HDF5 segfaulted at exit) and nothing
// half-written (last.pt.tmp, an empty config.json and log.csv, a staging folder).
TEST(Cli, AFullDiskIsAnErrorNamingTheFileAndLeavesNothing) {
  const fs::path dir = fs::temp_directory_path() / ("gnn_full_disk_" + std::to_string(getpid()));
  fs::remove_all(dir);
  tiny::write(dir / "data");
  const std::string data = (dir / "data").string();
  const std::string train = std::string(SPILL_TRAIN_EXE) + " --config " + SPILL_SOURCE_DIR +
                            "/configs/training/gns_smoke.json --data " + data +
                            " --threads 1 --set /steps=10 --set /checkpoint_every=10";
  ASSERT_EQ(run(train + " --out " + (dir / "run").string()), 0);
  const std::string infer = std::string(SPILL_INFER_EXE) + " ";
  const std::string ckpt = " --checkpoint " + (dir / "run/last.pt").string() + " --data " + data +
                           " --threads 1" +
                           " --replay-recorded-sources";  // the tiny dataset has no scene
  const fs::path out = dir / "out", log = dir / "log.txt";
  const std::vector<std::pair<std::string, int>> cases = {
      {train + " --out " + out.string(), 0},                                  // log.csv
      {train + " --out " + out.string(), 40},                                 // last.pt
      {infer + "rollout" + ckpt + " --frames 10 --out " + out.string(), 0},   // metadata.json
      {infer + "rollout" + ckpt + " --frames 10 --out " + out.string(), 16},  // rollout.h5
      {infer + "eval" + ckpt + " --out " + out.string(), 0}};                 // eval.json
  for (const auto& [command, blocks] : cases) {
    SCOPED_TRACE(command + " with files limited to " + std::to_string(blocks) + " blocks");
    const auto r = testing_support::run_with_file_size_limit(command, blocks, log);
    testing_support::expect_failed_write(r, dir);
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string name = e.path().filename().string();
      EXPECT_TRUE(name == "data" || name == "run") << "left over: " << e.path();
    }
  }
  fs::remove_all(dir);
}
