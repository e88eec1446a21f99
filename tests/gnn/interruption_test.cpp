// Ctrl-C and SIGTERM on spill-train and spill-infer, sent by a real signal to the running
// executable (common/exit_codes.h: exit 130 with a message, nothing half-written): during the
// simulation of `spill-train --scene --save-data`, during training (before the first checkpoint
// and while checkpoints are written every step), and during `spill-infer eval`.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "gnn/training/checkpoint.h"
#include "tests/gnn/tiny_dataset.h"

namespace fs = std::filesystem;

namespace {

struct Interrupted {
  bool signalled = false;  // the signal was sent (the command had not finished before)
  int code = -1;           // exit code; -1 when killed by a signal
  std::string output;      // stdout and stderr
};

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs `argv` with its output to `log`, sends `signal` once `ready()` holds (polled every 10 ms,
// at most 120 s) and waits for it to end.
Interrupted interrupt_when(const std::vector<std::string>& argv, const fs::path& log,
                           const std::function<bool()>& ready, int signal) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  Interrupted r;
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(pid, &status, WNOHANG) == pid) {  // ended before the signal
      r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      r.output = read_text(log);
      return r;
    }
    if (ready()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(pid, signal);
  r.signalled = true;
  waitpid(pid, &status, 0);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.output = read_text(log);
  return r;
}

// Whether a `.NAME.partial-PID` staging folder (common/output_folder.h) is in `dir`.
bool has_staging(const fs::path& dir, const std::string& name) {
  if (!fs::exists(dir)) return false;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind("." + name + ".partial-", 0) == 0) return true;
  return false;
}

// The files of `dir` whose names a half-written file would have (atomic writes stage beside
// the target), or any name not in `expected`.
std::vector<std::string> unexpected_files(const fs::path& dir,
                                          const std::vector<std::string>& expected) {
  std::vector<std::string> odd;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (std::find(expected.begin(), expected.end(), name) == expected.end()) odd.push_back(name);
  }
  return odd;
}

size_t lines_of(const fs::path& file) {
  const std::string text = read_text(file);
  return size_t(std::count(text.begin(), text.end(), '\n'));
}

class Interruption : public ::testing::TestWithParam<int> {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("spill_interrupt_" + std::to_string(getpid()) + "_" + std::to_string(GetParam()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  std::vector<std::string> train(const std::vector<std::string>& extra) const {
    std::vector<std::string> argv = {
        SPILL_TRAIN_EXE, "--config",
        std::string(SPILL_SOURCE_DIR) + "/configs/training/gns_smoke.json", "--threads", "1"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return argv;
  }
  fs::path dir_;
};

std::string signal_name(int s) {
  return s == SIGINT ? "SIGINT" : "SIGTERM";
}

}  // namespace

// While checkpoints are written every step, the run stops between steps: exit 130, a message
// naming the step its last.pt keeps, a last.pt that loads and holds that step (never a torn
// one), no staged file left, and --resume goes on from it.
TEST_P(Interruption, TrainingKeepsItsLastCheckpointAndResumes) {
  tiny::write(dir_ / "data");
  const fs::path run = dir_ / "run";
  const std::vector<std::string> settings = {"--set", "/checkpoint_every=1", "/log_every=1",
                                             "/validate_every=1000000"};
  auto argv =
      train({"--data", (dir_ / "data").string(), "--out", run.string(), "--set", "/steps=1000000"});
  argv.insert(argv.end(), settings.begin(), settings.end());
  const Interrupted r = interrupt_when(
      argv, dir_ / "train.log",
      [&] { return fs::exists(run / "last.pt") && lines_of(run / "log.csv") > 5; }, GetParam());
  ASSERT_TRUE(r.signalled) << r.output;
  EXPECT_EQ(r.code, 130) << r.output;
  std::smatch kept;
  ASSERT_TRUE(std::regex_search(r.output, kept,
                                std::regex("spill-train: interrupted at step "
                                           "[0-9]+ of 1000000; .*last\\.pt keeps "
                                           "step ([0-9]+)")))
      << r.output;
  const int64_t step = std::stoll(kept[1]);
  EXPECT_EQ(gnn::load_checkpoint((run / "last.pt").string()).state.step, step);
  EXPECT_TRUE(unexpected_files(run, {"config.json", "log.csv", "loss.svg", "last.pt"}).empty())
      << unexpected_files(run, {"config.json", "log.csv", "loss.svg", "last.pt"}).front();

  auto resume = train({"--data", (dir_ / "data").string(), "--out", run.string(), "--resume",
                       "--set", "/steps=" + std::to_string(step + 2)});
  resume.insert(resume.end(), settings.begin() + 1, settings.end());
  std::string command;
  for (const auto& a : resume) command += a + " ";
  EXPECT_EQ(std::system((command + "> " + (dir_ / "resume.log").string() + " 2>&1").c_str()), 0)
      << read_text(dir_ / "resume.log");
  EXPECT_EQ(gnn::load_checkpoint((run / "last.pt").string()).state.step, step + 2);
}

// A new run stopped before its first checkpoint holds nothing to resume: its folder is removed.
TEST_P(Interruption, NewRunWithoutACheckpointLeavesNoFolder) {
  tiny::write(dir_ / "data");
  const fs::path run = dir_ / "run";
  const Interrupted r = interrupt_when(
      train({"--data", (dir_ / "data").string(), "--out", run.string(), "--set", "/steps=1000000",
             "/checkpoint_every=1000000", "/log_every=1", "/validate_every=1000000"}),
      dir_ / "train.log", [&] { return lines_of(run / "log.csv") > 2; }, GetParam());
  ASSERT_TRUE(r.signalled) << r.output;
  EXPECT_EQ(r.code, 130) << r.output;
  EXPECT_NE(r.output.find("no checkpoint was written yet"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(run));
}

// Stopped while simulating its data, spill-train --scene --save-data leaves neither the dataset
// (nor its staging folder) nor a run folder.
TEST_P(Interruption, SceneSimulationLeavesNoDatasetAndNoRun) {
  // A dam break of about 1,000 particles over 2 s: long enough to be interrupted in.
  std::ofstream(dir_ / "scene.json") << R"({
    "name": "interrupted", "particle_radius": 0.01, "end_time": 2, "output": {"frame_dt": 0.02},
    "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2], "velocity": [0, 0, 0]}]})";
  const Interrupted r = interrupt_when(
      train({"--scene", (dir_ / "scene.json").string(), "--trajectories", "3", "--split",
             "0.34/0.33/0.33", "--out", (dir_ / "run").string(), "--save-data",
             (dir_ / "saved").string()}),
      dir_ / "train.log", [&] { return has_staging(dir_, "saved"); }, GetParam());
  ASSERT_TRUE(r.signalled) << r.output;
  EXPECT_EQ(r.code, 130) << r.output;
  EXPECT_NE(r.output.find("spill-train: interrupted at frame"), std::string::npos) << r.output;
  EXPECT_FALSE(has_staging(dir_, "saved"));
  EXPECT_FALSE(fs::exists(dir_ / "saved"));
  EXPECT_FALSE(fs::exists(dir_ / "run"));
}

// spill-infer eval stops at its next frame, writing nothing. The model is made large enough
// (wide and deep) that its rollouts outlast the wait for the signal.
TEST_P(Interruption, EvalWritesNothing) {
  tiny::write(dir_ / "data");
  const std::string checkpoint = (dir_ / "model" / "last.pt").string();
  std::string command;
  for (const auto& a :
       train({"--data", (dir_ / "data").string(), "--out", (dir_ / "model").string(), "--set",
              "/steps=2", "/model/latent=256", "/model/layers=6"}))
    command += a + " ";
  ASSERT_EQ(std::system((command + "> /dev/null 2>&1").c_str()), 0);
  const Interrupted r = interrupt_when(
      {SPILL_INFER_EXE, "eval", "--checkpoint", checkpoint, "--data", (dir_ / "data").string(),
       "--split", "train", "--threads", "1", "--replay-recorded-sources",  // tiny: no scene
       "--out", (dir_ / "eval").string()},
      dir_ / "eval.log", [&] { return has_staging(dir_, "eval"); }, GetParam());
  ASSERT_TRUE(r.signalled) << r.output;
  EXPECT_EQ(r.code, 130) << r.output;
  EXPECT_NE(r.output.find("spill-infer: interrupted at frame"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("nothing written"), std::string::npos) << r.output;
  EXPECT_FALSE(has_staging(dir_, "eval"));
  EXPECT_FALSE(fs::exists(dir_ / "eval"));
}

INSTANTIATE_TEST_SUITE_P(Signals, Interruption, ::testing::Values(SIGINT, SIGTERM),
                         [](const auto& info) { return signal_name(info.param); });
