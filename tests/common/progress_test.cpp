// Progress lines (common/progress.h): before any work is done there is no rate to extrapolate,
// so the ETA says "unknown" (a reach stuck at steps of 1e-12 s printed "eta 0.0s"); once work is
// done it is extrapolated from the rate so far.

#include "common/progress.h"

#include <gtest/gtest.h>

#include <sstream>
#include <thread>

TEST(Progress, TheEtaIsUnknownUntilSomeWorkIsDone) {
  std::ostringstream out;
  common::ProgressReporter progress(out, false, 1000, "reach");
  progress.update(0, "t=1e-09s of 600s");
  EXPECT_NE(out.str().find("eta unknown"), std::string::npos) << out.str();
  EXPECT_EQ(out.str().find("eta 0.0s"), std::string::npos) << out.str();
  out.str("");
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  progress.update(500, "t=300s of 600s");  // half done: the ETA is the time so far
  const std::string line = out.str();
  const size_t at = line.find("eta ");
  ASSERT_NE(at, std::string::npos) << line;
  const double eta = std::stod(line.substr(at + 4));
  EXPECT_GE(eta, 0.05) << line;
  EXPECT_LT(eta, 5.0) << line;
}
