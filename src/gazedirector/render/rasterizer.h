#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace gazedirector {

// Sub-pixel precision of the rasterizer: vertices snap to 1/16 pixel, so edge
// functions are exact integers, shared edges are watertight and every render
// is bit-for-bit reproducible.
inline constexpr int kSubpixelBits = 4;

// A vertex on screen, snapped: x and y in 1/16 pixels (pixel centres at
// multiples of 16), z the depth in millimetres. Padded to 16 bytes, so that
// one aligned vector load reads a vertex.
struct alignas(16) ScreenVertex {
  int32_t x, y;
  float z;
  int32_t unused = 0;
};

// Snaps pixel coordinates (pixel centres at integers) and a depth. Vertices
// beyond +-65536 px are clamped; triangles that reach them are skipped.
inline ScreenVertex SnapVertex(float x, float y, float z) {
  constexpr float kScale = 1 << kSubpixelBits, kClamp = 65536.0f;
  const float sx = std::clamp(x, -kClamp, kClamp) * kScale, sy = std::clamp(y, -kClamp, kClamp) * kScale;
  // Round half away from zero, the same on every machine.
  return {static_cast<int32_t>(sx + (sx >= 0 ? 0.5f : -0.5f)), static_cast<int32_t>(sy + (sy >= 0 ? 0.5f : -0.5f)), z};
}

// Projects camera-frame points (x, y, z columns, z > 0 in front) through a
// pinhole (focal lengths and principal point in pixels) and snaps them:
// SnapVertex(fx * x / z + cx, fy * y / z + cy, z), eight at a time with AVX2.
void ProjectVertices(const float* xyz, int count, float fx, float fy, float cx, float cy, ScreenVertex* out);

// What each pixel sees: the nearest triangle (an id the caller chose, -1 for
// none), its depth and the barycentric weights of its vertices 1 and 2
// (vertex 0 has 1 - b1 - b2).
class VisibilityBuffer {
 public:
  // Clears to empty; allocates only when the size grows.
  void Reset(int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }
  int size() const { return width_ * height_; }
  float depth(int pixel) const { return depth_[pixel]; }
  int32_t triangle(int pixel) const { return triangle_[pixel]; }
  float b1(int pixel) const { return b1_[pixel]; }
  float b2(int pixel) const { return b2_[pixel]; }
  bool covered(int pixel) const { return triangle_[pixel] >= 0; }
  const int32_t* triangle_data() const { return triangle_.data(); }
  const float* b1_data() const { return b1_.data(); }
  const float* b2_data() const { return b2_.data(); }

  // An attribute given as one column per vertex, at a covered pixel whose
  // triangle's vertices are the columns `corners` of `values` (an expression
  // that reads `values`: assign it to a vector while `values` lives).
  template <typename Columns>
  auto Interpolate(int pixel, const Columns& values, const Eigen::Vector3i& corners) const {
    const float w1 = b1_[pixel], w2 = b2_[pixel], w0 = 1.0f - w1 - w2;
    return w0 * values.col(corners[0]) + w1 * values.col(corners[1]) + w2 * values.col(corners[2]);
  }

  // Rasterizes the triangles that face the camera (meshes are wound
  // counter-clockwise seen from outside) with a depth test; covered pixels
  // store id_offset + the triangle's index. Triangles with a vertex nearer
  // than 1 mm or beyond 8192 px are skipped.
  // `clip` (x0, y0, x1, y1, inclusive pixels) limits drawing to a window.
  void Draw(const ScreenVertex* vertices, const Eigen::Vector3i* triangles, int num_triangles, int32_t id_offset);
  void Draw(const ScreenVertex* vertices, const Eigen::Vector3i* triangles, int num_triangles, int32_t id_offset,
            const Eigen::Vector4i& clip);

  // The indices of covered pixels, in raster order.
  void CollectCovered(std::vector<int>& pixels) const;

  // Whether vector instructions are used where the build has them (the
  // default): with AVX2, rows are filled eight pixels at a time (triangles up
  // to four pixels wide two rows at a time, and those up to six pixels wide
  // and high eight triangles at a time, one per lane), triangles set up eight
  // at a time, covered pixels collected eight at a time. Off, everything takes the scalar
  // path. Both give identical buffers and pixel lists (up to which of two
  // triangles wins a pixel centre they reach at exactly the same depth).
  void set_vectorized(bool on) { vectorized_ = on; }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<float> depth_;
  std::vector<int32_t> triangle_;
  std::vector<float> b1_;
  std::vector<float> b2_;

  struct Prepared;
  struct PreparedBatch;
  void DrawOne(const ScreenVertex* vertices, const Eigen::Vector3i& triangle, int32_t id, const Eigen::Vector4i& clip);
  void DrawBatches(const ScreenVertex* vertices, const Eigen::Vector3i* triangles, int num_triangles, int32_t id_offset,
                   const Eigen::Vector4i& clip);
  void FillRows(const PreparedBatch& batch, int lane, int32_t id);
  void FillRowsVectorized(const PreparedBatch& batch, int lane, int32_t id);
  void FillRowPairs(const PreparedBatch& batch, int lane, int32_t id);
  unsigned FillStamps(const PreparedBatch& batch, unsigned lanes, int32_t first_id);
  void FillLarge(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c, int64_t area, int x0, int x1,
                 int y0, int y1, int32_t id);

  bool vectorized_ = true;
};

}  // namespace gazedirector
