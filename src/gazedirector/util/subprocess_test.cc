#include "gazedirector/util/subprocess.h"

#include <optional>
#include <string>

#include <gtest/gtest.h>

namespace gazedirector {
namespace {

TEST(SubprocessTest, RunForOutputReturnsStdoutOnlyWhenTheProgramSucceeds) {
  const std::optional<std::string> listed = RunForOutput({"printf", "%s\\n%s", "one", "two"});
  ASSERT_TRUE(listed.has_value());
  EXPECT_EQ(*listed, "one\ntwo");
  EXPECT_FALSE(RunForOutput({"false"}).has_value());
  EXPECT_FALSE(RunForOutput({"gazedirector-no-such-program"}).has_value());
  // Its stdin is empty, so a program that reads it ends at once.
  const std::optional<std::string> echoed = RunForOutput({"cat"});
  ASSERT_TRUE(echoed.has_value());
  EXPECT_TRUE(echoed->empty());
}

TEST(SubprocessTest, RunForOutputReadsMoreThanAPipeHolds) {
  // 200,000 bytes: more than a pipe's buffer, so the reader must drain while the child writes.
  const std::optional<std::string> output = RunForOutput({"head", "-c", "200000", "/dev/zero"});
  ASSERT_TRUE(output.has_value());
  EXPECT_EQ(output->size(), 200000u);
}

TEST(SubprocessTest, ProgramExistsLooksInPath) {
  EXPECT_TRUE(ProgramExists("sh"));
  EXPECT_FALSE(ProgramExists("gazedirector-no-such-program"));
}

}  // namespace
}  // namespace gazedirector
