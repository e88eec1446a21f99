// Output folders never take what is not ours: `--out .` and friends are refused, a trailing slash
// names the folder itself, an earlier result survives a failed replacement, and staging folders of
// dead processes are cleaned up.

#include "common/output_folder.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace common {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / (name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Runs `body` with the working folder set to `dir`, restoring it afterwards.
template <class F>
void in_folder(const fs::path& dir, F body) {
  const fs::path old = fs::current_path();
  fs::current_path(dir);
  try {
    body();
  } catch (...) {
    fs::current_path(old);
    throw;
  }
  fs::current_path(old);
}

OutputFolderPolicy ours(bool replace) {
  OutputFolderPolicy p;
  p.markers = {"metadata.json"};
  p.replace = replace;
  return p;
}

void expect_refused(const std::string& given, const OutputFolderPolicy& policy,
                    const std::string& words) {
  try {
    OutputFolder out(given, policy);
    ADD_FAILURE() << given << ": expected a refusal";
  } catch (const OutputPathError& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--out " + given), std::string::npos) << e.what();
  }
}

TEST(OutputFolder, TrailingSlashNamesTheFolderItself) {
  EXPECT_EQ(normalise_output_path("/a/b/"), fs::path("/a/b"));
  EXPECT_EQ(normalise_output_path("/a/b/."), fs::path("/a/b"));
  EXPECT_EQ(normalise_output_path("/a/./c/../b//"), fs::path("/a/b"));
  EXPECT_EQ(normalise_output_path("/"), fs::path("/"));
  EXPECT_THROW(normalise_output_path(""), OutputPathError);

  const fs::path dir = fresh_dir("output_slash");
  {
    OutputFolder out((dir / "new").string() + "/", ours(false));
    EXPECT_EQ(out.staging().parent_path(), dir);  // beside the target, not inside it
    std::ofstream(out.staging() / "metadata.json") << "{}";
    out.commit();
  }
  EXPECT_TRUE(fs::exists(dir / "new" / "metadata.json"));
  {
    OutputFolder out((dir / "new").string() + "/", ours(true));
    std::ofstream(out.staging() / "metadata.json") << "{\"second\": 1}";
    out.commit();
  }
  std::ifstream in(dir / "new" / "metadata.json");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text, "{\"second\": 1}");
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename(), "new") << "left over: " << e.path();
  fs::remove_all(dir);
}

TEST(OutputFolder, RefusesTheWorkingFolderItsParentsRootHomeAndInputs) {
  const fs::path dir = fresh_dir("output_refuse");
  fs::create_directories(dir / "work" / "sub");
  std::ofstream(dir / "work" / "metadata.json") << "{}";  // even a folder that looks like ours
  std::ofstream(dir / "work" / "notes.txt") << "precious";
  in_folder(dir / "work", [&] {
    for (const std::string& given :
         std::vector<std::string>{".", "./", "..", "../work", (dir / "work").string()})
      expect_refused(given, ours(true), "current folder");
  });
  in_folder(dir / "work" / "sub", [&] { expect_refused("..", ours(true), "current folder"); });
  expect_refused("/", ours(true), "root");
  const std::string old_home = std::getenv("HOME") ? std::getenv("HOME") : "";
  setenv("HOME", (dir / "work").c_str(), 1);
  expect_refused((dir / "work").string(), ours(true), "home folder");
  setenv("HOME", old_home.c_str(), 1);
  OutputFolderPolicy with_input = ours(true);
  with_input.inputs = {dir / "work" / "sub" / "scene.json"};
  expect_refused((dir / "work").string(), with_input, "holds the input");
  EXPECT_TRUE(fs::exists(dir / "work" / "notes.txt"));
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename(), "work") << "left over: " << e.path();
  fs::remove_all(dir);
}

TEST(OutputFolder, ReplacesOnlyItsOwnFoldersAndOnlyAfterSuccess) {
  const fs::path dir = fresh_dir("output_replace");
  fs::create_directories(dir / "theirs");
  std::ofstream(dir / "theirs" / "notes.txt") << "precious";
  expect_refused((dir / "theirs").string(), ours(false), "already exists");
  expect_refused((dir / "theirs").string(), ours(true), "no metadata.json");
  EXPECT_TRUE(fs::exists(dir / "theirs" / "notes.txt"));

  fs::create_directories(dir / "run");
  std::ofstream(dir / "run" / "metadata.json") << "old";
  {
    OutputFolder out((dir / "run").string(), ours(true));
    std::ofstream(out.staging() / "metadata.json") << "new";
    // No commit: the new result failed, the old one stays and the staging folder goes.
  }
  std::ifstream in(dir / "run" / "metadata.json");
  std::string text;
  in >> text;
  EXPECT_EQ(text, "old");
  int entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) entries += e.is_directory() ? 1 : 0;
  EXPECT_EQ(entries, 2) << "only theirs/ and run/ may remain";
  fs::remove_all(dir);
}

TEST(OutputFolder, StagingOfDeadProcessesIsRemovedAndLiveOnesKept) {
  const fs::path dir = fresh_dir("output_stale");
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);  // its PID now names no process
  const fs::path dead = dir / (".run.partial-" + std::to_string(child));
  const fs::path dead_old = dir / (".other.old-" + std::to_string(child));
  const fs::path live = dir / (".run.partial-" + std::to_string(getppid()));
  const fs::path unrelated = dir / ".cache.partial-x";
  for (const fs::path& p : {dead, dead_old, live, unrelated}) fs::create_directories(p);
  std::ostringstream log;
  OutputFolderPolicy policy = ours(false);
  policy.log = &log;
  OutputFolder out((dir / "new").string(), policy);
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_FALSE(fs::exists(dead_old));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(unrelated));
  EXPECT_NE(log.str().find(dead.string()), std::string::npos) << log.str();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace common
