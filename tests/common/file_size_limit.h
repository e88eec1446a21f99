#pragma once
// Runs a command as on a full disk: files it writes may not grow past a limit (ulimit -f) and
// SIGXFSZ is ignored, so a write past the limit fails with EFBIG as one fails with ENOSPC when the
// disk is full. Needs no root and no small file system.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace testing_support {

struct LimitedRun {
  int exit_code = -1;  // 128 + N when the command died of signal N
  std::string output;  // stdout and stderr, the last 4000 bytes
};

// `limit_blocks` is in the shell's ulimit -f blocks (512 bytes in dash). The output goes through
// a pipe, which the limit does not touch, so the error message is seen even at a limit of 0.
inline LimitedRun run_with_file_size_limit(const std::string& command, int limit_blocks,
                                           const std::filesystem::path& output_file) {
  const std::string script = "( trap '' XFSZ; ulimit -f " + std::to_string(limit_blocks) + "; " +
                             command + "; echo \"exit=$?\" ) 2>&1 | tail -c 4000 > " +
                             output_file.string();
  const int status = std::system(script.c_str());
  LimitedRun out;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return out;
  std::ifstream in(output_file);
  out.output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  const auto at = out.output.rfind("exit=");
  if (at != std::string::npos) out.exit_code = std::atoi(out.output.c_str() + at + 5);
  std::filesystem::remove(output_file);
  return out;
}

// What every command must do when a write fails: exit 1 (no signal), naming a file under
// `folder`, saying that it could not write.
inline void expect_failed_write(const LimitedRun& r, const std::filesystem::path& folder) {
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(folder.string()), std::string::npos) << r.output;
  EXPECT_TRUE(r.output.find("cannot write") != std::string::npos ||
              r.output.find("failed") != std::string::npos)
      << r.output;
}

}  // namespace testing_support
