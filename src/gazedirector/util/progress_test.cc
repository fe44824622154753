#include "gazedirector/util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <string>

#include <gtest/gtest.h>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::CapturedLog;

int CountLines(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

TEST(ProgressTest, DurationsReadAsMinutesAndSecondsOrHours) {
  EXPECT_EQ(FormatDuration(0), "0:00");
  EXPECT_EQ(FormatDuration(59.4), "0:59");
  EXPECT_EQ(FormatDuration(59.6), "1:00");
  EXPECT_EQ(FormatDuration(605), "10:05");
  EXPECT_EQ(FormatDuration(3600), "1:00:00");
  EXPECT_EQ(FormatDuration(3 * 3600 + 62), "3:01:02");
  EXPECT_EQ(FormatDuration(-5), "0:00") << "never a negative time left";
}

TEST(ProgressTest, QuietProgressSaysNothing) {
  const CapturedLog log;
  ::testing::internal::CaptureStderr();
  {
    Progress progress("track", 50, "frames", /*quiet=*/true);
    for (long done = 1; done <= 50; ++done) progress.Update(done);
    progress.Finish();
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_EQ(log.text(), "");
}

// Where stderr is not a terminal (a log file, CI), progress is a log line per
// tenth of the work and one at the end, not a redrawn bar.
TEST(ProgressTest, LogsEachTenthAndTheTotalWhenNotOnATerminal) {
  if (::isatty(STDERR_FILENO)) GTEST_SKIP() << "stderr is a terminal: progress draws a bar there";
  const CapturedLog log;
  ::testing::internal::CaptureStderr();
  {
    Progress progress("redirect", 200, "frames");
    for (long done = 1; done <= 200; ++done) progress.Update(done);
    progress.Finish();
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "") << "no bar drawn";
  const std::string text = log.text();
  EXPECT_EQ(CountLines(text), 11) << text;
  EXPECT_EQ(text.rfind("redirect: 20/200 frames (10%), ", 0), 0u) << text;
  EXPECT_NE(text.find("redirect: 200/200 frames (100%)"), std::string::npos) << text;
  EXPECT_NE(text.find("redirect: 200 frames in 0:00 ("), std::string::npos) << text;
}

}  // namespace
}  // namespace gazedirector
