#include "gazedirector/io/mapped_file.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gazedirector/io/binary_io.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;

std::string Text(std::span<const std::byte> bytes) { return {reinterpret_cast<const char*>(bytes.data()), bytes.size()}; }

TEST(MappedFileTest, MapsAFileAndKeepsItsBytesWhenTheFileIsReplaced) {
  const fs::path dir = testing::ScratchDir("mapped_file");
  const fs::path path = dir / "cache.bin";
  std::ofstream(path, std::ios::binary) << "first version";
  const std::optional<MappedFile> file = MappedFile::Open(path);
  ASSERT_TRUE(file);
  EXPECT_EQ(Text(file->bytes()), "first version");
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(file->bytes().data()) % 4096, 0u) << "starts on a page";

  // Caches are replaced by renaming a new file over the old one.
  std::ofstream(dir / "new.bin", std::ios::binary) << "second";
  fs::rename(dir / "new.bin", path);
  EXPECT_EQ(Text(file->bytes()), "first version");
  EXPECT_EQ(Text(MappedFile::Open(path)->bytes()), "second");

  std::optional<MappedFile> moved = std::move(*MappedFile::Open(path));
  EXPECT_EQ(Text(moved->bytes()), "second");
}

TEST(MappedFileTest, NothingIsMappedForAMissingEmptyOrOtherFile) {
  const fs::path dir = testing::ScratchDir("mapped_file");
  EXPECT_FALSE(MappedFile::Open(dir / "missing.bin"));
  std::ofstream(dir / "empty.bin", std::ios::binary).flush();
  EXPECT_FALSE(MappedFile::Open(dir / "empty.bin"));
  EXPECT_FALSE(MappedFile::Open(dir));
}

// Arrays written aligned are read where they lie, whatever came before them;
// a file cut short or a count past its end reads as nothing.
TEST(MappedFileTest, AlignedArraysAreReadWhereTheyLieAndCutOnesAreRefused) {
  const fs::path path = testing::ScratchDir("mapped_file") / "arrays.bin";
  const std::vector<float> values = {1.5f, -2.25f, 3.0f};
  for (const std::string& prefix : {std::string(), std::string(1, 'x'), std::string(61, 'y')}) {
    {
      std::ofstream out(path, std::ios::binary);
      out << prefix;
      WriteVector(out, std::vector<uint64_t>{7, 8});
      WriteAlignedVector(out, values);
      WriteVector(out, std::vector<char>{'e', 'n', 'd'});
    }
    const std::optional<MappedFile> file = MappedFile::Open(path);
    ASSERT_TRUE(file);
    std::span<const std::byte> rest = file->bytes().subspan(prefix.size());
    std::vector<uint64_t> counts;
    std::span<const float> viewed;
    std::vector<char> end;
    ASSERT_TRUE(ReadVector(rest, counts, 10));
    ASSERT_TRUE(ViewAlignedVector(rest, viewed, 10));
    ASSERT_TRUE(ReadVector(rest, end, 10));
    EXPECT_EQ(counts, (std::vector<uint64_t>{7, 8}));
    EXPECT_EQ(std::vector<float>(viewed.begin(), viewed.end()), values) << prefix.size();
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(viewed.data()) % kArrayAlignment, 0u);
    EXPECT_EQ(std::string(end.begin(), end.end()), "end");
    EXPECT_TRUE(rest.empty());

    std::span<const std::byte> cut = file->bytes().subspan(prefix.size(), file->bytes().size() - prefix.size() - 4);
    ASSERT_TRUE(ReadVector(cut, counts, 10));
    ASSERT_TRUE(ViewAlignedVector(cut, viewed, 10));
    EXPECT_FALSE(ReadVector(cut, end, 10)) << "the last array is cut";
    std::span<const std::byte> again = file->bytes().subspan(prefix.size());
    EXPECT_FALSE(ReadVector(again, counts, 1)) << "more values than allowed";
  }
}

}  // namespace
}  // namespace gazedirector
