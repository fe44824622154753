#include "gazedirector/io/atomic_output.h"

#include <fstream>
#include <functional>
#include <sstream>

#include <gtest/gtest.h>

#include "gazedirector/util/error.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& path) {
  std::ifstream stream(path, std::ios::binary);
  std::stringstream text;
  text << stream.rdbuf();
  return text.str();
}

void Write(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

ExitCode FailureOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& error) {
    return error.code();
  }
  return ExitCode::kOk;
}

// The output appears only at Commit, whole; until then an older file of that
// name keeps its content, and a writer that stops early leaves nothing behind.
TEST(AtomicOutputTest, TheOutputAppearsWholeAtCommitAndNeverHalfWritten) {
  const fs::path dir = testing::ScratchDir("atomic_output");
  const fs::path path = dir / "new" / "fits.jsonl";  // the folder is created
  {
    AtomicOutput output(path);
    EXPECT_EQ(output.temp_path().extension(), ".jsonl");
    Write(output.temp_path(), "first\n");
    EXPECT_FALSE(fs::exists(path));
    output.Commit();
  }
  EXPECT_EQ(Read(path), "first\n");
  {
    AtomicOutput output(path);
    Write(output.temp_path(), "half of the sec");
    EXPECT_EQ(Read(path), "first\n");
  }  // not committed: an error or an interrupt
  EXPECT_EQ(Read(path), "first\n");
  EXPECT_TRUE(testing::NoPartialFiles(dir));
  // Nothing written is an error, not an empty file.
  EXPECT_EQ(FailureOf([&] { AtomicOutput(dir / "empty.png").Commit(); }), ExitCode::kOutput);
  EXPECT_FALSE(fs::exists(dir / "empty.png"));
}

// An output that names an input (by another spelling, too) or a folder is
// refused before anything is written; the input keeps its content.
TEST(AtomicOutputTest, InputsAndFoldersAreNeverOverwritten) {
  const fs::path dir = testing::ScratchDir("atomic_output_inputs");
  const fs::path input = dir / "photo.jpg";
  Write(input, "the photo");
  EXPECT_EQ(FailureOf([&] { WriteTextFile(dir / "." / "photo.jpg", "redirected", {input}); }), ExitCode::kOutput);
  EXPECT_EQ(Read(input), "the photo");
  EXPECT_EQ(FailureOf([&] { WriteTextFile(dir, "text"); }), ExitCode::kOutput);
  EXPECT_TRUE(fs::is_directory(dir));
  WriteTextFile(dir / "notes.txt", "text", {input});
  EXPECT_EQ(Read(dir / "notes.txt"), "text");
  EXPECT_TRUE(testing::NoPartialFiles(dir));
}

// Commands check their outputs before their work: a path that can take a file
// passes and is left as it was (no probe file, an older file untouched), one
// whose folder cannot be made or takes no new files fails as an output error.
TEST(AtomicOutputTest, AnOutputIsCheckedWritableWithoutLeavingATrace) {
  const fs::path dir = testing::ScratchDir("atomic_output_writable");
  RequireWritable(dir / "new" / "gaze.csv");
  EXPECT_TRUE(fs::is_directory(dir / "new"));
  EXPECT_TRUE(fs::is_empty(dir / "new"));
  Write(dir / "old.csv", "older results");
  RequireWritable(dir / "old.csv");
  EXPECT_EQ(Read(dir / "old.csv"), "older results");
  EXPECT_EQ(FailureOf([&] { RequireWritable(dir / "old.csv" / "gaze.csv"); }), ExitCode::kOutput);
  EXPECT_EQ(FailureOf([&] { RequireWritable("/proc/gazedirector_gaze.csv"); }), ExitCode::kOutput);
  EXPECT_EQ(FailureOf([&] { RequireWritable(dir); }), ExitCode::kOutput);
  EXPECT_TRUE(testing::NoPartialFiles(dir));
}

}  // namespace
}  // namespace gazedirector
