// The one exit-code policy (common/exit_codes.h): input errors exit 2, interruptions 130, the
// rest 1, and running out of memory says so in words rather than "std::bad_alloc".

#include "common/exit_codes.h"

#include <gtest/gtest.h>

#include <new>
#include <sstream>

#include "common/config_error.h"

TEST(ExitCodes, EachKindOfErrorHasItsCodeAndAMessage) {
  std::ostringstream out;
  EXPECT_EQ(common::report_error(out, "p", common::ConfigError("s.json", "/a", "bad")), 2);
  EXPECT_NE(out.str().find("p: error: s.json:/a: bad"), std::string::npos) << out.str();
  EXPECT_EQ(common::report_error(out, "p", common::Interrupted("stopped")), 130);
  EXPECT_EQ(common::report_error(out, "p", std::runtime_error("blew up")), 1);
  out.str("");
  EXPECT_EQ(common::report_error(out, "p", std::bad_alloc()), 1);
  EXPECT_NE(out.str().find("out of memory"), std::string::npos) << out.str();
  // A command that allocates no particles says what it does allocate.
  out.str("");
  EXPECT_EQ(common::report_error(out, "p", std::bad_alloc(), "release fewer elements"), 1);
  EXPECT_NE(out.str().find("release fewer elements, or a machine"), std::string::npos) << out.str();
  EXPECT_EQ(out.str().find("particles"), std::string::npos) << out.str();
}
