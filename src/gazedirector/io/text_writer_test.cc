#include "gazedirector/io/text_writer.h"

#include <gtest/gtest.h>

#include "gazedirector/util/error.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;

TEST(TextWriterTest, ACsvAppearsWithItsHeaderOnlyWhenFinished) {
  const fs::path path = testing::ScratchDir("csv_finished") / "gaze.csv";
  CsvWriter csv(path, {"frame", "gaze_angle_x"});
  csv.AddRow({"0", "0.125"});
  csv.AddRow({"1", "-0.5"});
  EXPECT_FALSE(fs::exists(path)) << "nothing at the final path before Finish";
  csv.Finish();
  EXPECT_EQ(testing::ReadText(path), "frame,gaze_angle_x\n0,0.125\n1,-0.5\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(path.parent_path()), fs::directory_iterator()), 1)
      << "no temporary file left beside it";
}

// A row of the wrong width is a bug, refused before it reaches the file; the
// unfinished file is then never seen.
TEST(TextWriterTest, ARowOfTheWrongWidthIsRefusedAndNothingIsLeft) {
  const fs::path dir = testing::ScratchDir("csv_refused");
  {
    CsvWriter csv(dir / "gaze.csv", {"frame", "gaze_angle_x"});
    try {
      csv.AddRow({"0"});
      ADD_FAILURE() << "a row of one value for two columns was written";
    } catch (const Error& error) {
      EXPECT_EQ(error.code(), ExitCode::kInternal);
      EXPECT_STREQ(error.what(), "CSV row with 1 values for 2 columns");
    }
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(TextWriterTest, NeverWritesOverAnInput) {
  const fs::path input = testing::ScratchDir("text_input") / "fits.jsonl";
  WriteTextFile(input, "{}\n");
  try {
    TextWriter writer(input, {input});
    ADD_FAILURE() << "a writer opened over its input";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ExitCode::kOutput);
  }
  EXPECT_EQ(testing::ReadText(input), "{}\n");
}

}  // namespace
}  // namespace gazedirector
