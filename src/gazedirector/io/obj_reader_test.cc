#include "gazedirector/io/obj_reader.h"

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "gazedirector/io/assets.h"
#include "gazedirector/model/eye_region_topology.h"
#include "gazedirector/util/error.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;

fs::path WriteFile(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path path = dir / name;
  std::ofstream(path) << text;
  return path;
}

// The error a reader raises: its exit code and its one line.
template <typename Read>
Error FailureOf(Read read) {
  try {
    read();
  } catch (const Error& error) {
    return error;
  }
  ADD_FAILURE() << "no error raised";
  return Error(ExitCode::kOk, "");
}

TEST(ObjReaderTest, ReadsTheEyeRegionMeshWithOneUvPerVertex) {
  const ObjMesh mesh = ReadObj(testing::TestAssets().eye_model() / "mesh" / "eye_region.obj");
  ASSERT_EQ(mesh.positions.size(), static_cast<std::size_t>(topology::kNumRegionVertices));
  ASSERT_EQ(mesh.uvs.size(), mesh.positions.size());
  ASSERT_GT(mesh.triangles.size(), 300u);
  for (const Eigen::Vector3i& triangle : mesh.triangles) {
    EXPECT_GE(triangle.minCoeff(), 0);
    EXPECT_LT(triangle.maxCoeff(), topology::kNumRegionVertices);
    EXPECT_NE(triangle[0], triangle[1]);
    EXPECT_NE(triangle[1], triangle[2]);
  }
  for (const Eigen::Vector2d& uv : mesh.uvs) {
    EXPECT_GE(uv.minCoeff(), 0.0);
    EXPECT_LE(uv.maxCoeff(), 1.0);
  }
}

TEST(ObjReaderTest, ReadsTrianglesWithOrWithoutTheirUvIndices) {
  const ObjMesh mesh = ReadObj(WriteFile(testing::ScratchDir("obj_plain"), "plain.obj",
                                         "# a comment\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                                         "vn 0 0 1\nf 1 2 3\nf 1/1 2/2 3/3\nf 1/1/1 2/2/1 3/3/1\nf 1//1 2//1 3//1\n"));
  ASSERT_EQ(mesh.positions.size(), 3u);
  ASSERT_EQ(mesh.triangles.size(), 4u);
  for (const Eigen::Vector3i& triangle : mesh.triangles) EXPECT_EQ(triangle, Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(mesh.positions[1], Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(mesh.uvs[2], Eigen::Vector2d(0, 1));
}

// A broken asset is the user's to mend: exit code 5 and the file and line,
// never a silent zero or an uncaught exception of the standard library.
TEST(ObjReaderTest, AMalformedRecordNamesItsFileAndLine) {
  const fs::path dir = testing::ScratchDir("obj_malformed");
  const std::string vertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const struct {
    std::string name, text, says;
  } cases[] = {
      {"short_vertex.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", "short_vertex.obj:2: malformed record"},
      {"short_uv.obj", vertices + "vt 0.5\n", "short_uv.obj:4: malformed record"},
      {"word_index.obj", vertices + "f 1 2 three\n", "word_index.obj:4: malformed record"},
      {"word_uv.obj", vertices + "vt 0 0\nvt 1 0\nvt 0 1\nf 1/a 2/2 3/3\n", "word_uv.obj:7: malformed record"},
      {"other_uv.obj", vertices + "vt 0 0\nvt 1 0\nvt 0 1\nf 1/2 2/2 3/3\n", "other_uv.obj:7: uv index differs"},
      {"quad.obj", vertices + "v 1 1 0\nf 1 2 4 3\n", "quad.obj:5: only triangles"},
      {"far_index.obj", vertices + "f 1 2 9\n", "far_index.obj: face index out of range"},
      {"uv_count.obj", vertices + "vt 0 0\nf 1 2 3\n", "uv_count.obj: 1 uvs for 3 vertices"},
  };
  for (const auto& c : cases) {
    const fs::path path = WriteFile(dir, c.name, c.text);
    const Error error = FailureOf([&] { ReadObj(path); });
    EXPECT_EQ(error.code(), ExitCode::kAssets) << c.name;
    EXPECT_NE(std::string(error.what()).find(c.says), std::string::npos) << error.what();
  }
  const Error missing = FailureOf([&] { ReadObj(dir / "none.obj"); });
  EXPECT_EQ(missing.code(), ExitCode::kAssets);
  EXPECT_NE(std::string(missing.what()).find("none.obj"), std::string::npos) << missing.what();
}

TEST(ObjReaderTest, ANumberTableTakesSpacesAndCommasAndSkipsBlankRows) {
  const fs::path dir = testing::ScratchDir("number_table");
  const auto rows = ReadNumberTable(WriteFile(dir, "table.txt", "1 2.5 -3\n\n4,5e-1, 6\n"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0], (std::vector<double>{1, 2.5, -3}));
  EXPECT_EQ(rows[1], (std::vector<double>{4, 0.5, 6}));

  const fs::path words = WriteFile(dir, "words.txt", "1 2 3\n4 five 6\n");
  const Error error = FailureOf([&] { ReadNumberTable(words); });
  EXPECT_EQ(error.code(), ExitCode::kAssets);
  EXPECT_NE(std::string(error.what()).find("words.txt: row 2 is not numeric"), std::string::npos) << error.what();
}

}  // namespace
}  // namespace gazedirector
