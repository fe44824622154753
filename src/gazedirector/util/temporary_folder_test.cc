#include "gazedirector/util/temporary_folder.h"

#include <gtest/gtest.h>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::ScopedEnv;

TEST(TemporaryFolderTest, IsTmpdirWhereThatIsAFolderElseTmp) {
  const std::filesystem::path folder = testing::ScratchDir("temporary_folder");
  {
    const ScopedEnv tmpdir("TMPDIR", folder.string());
    EXPECT_EQ(TemporaryFolder(), folder);
  }
  {
    const ScopedEnv tmpdir("TMPDIR", (folder / "no such folder").string());
    EXPECT_EQ(TemporaryFolder(), std::filesystem::path("/tmp"));
  }
}

}  // namespace
}  // namespace gazedirector
