#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace gazedirector {

// A vertex on screen: pixel coordinates (pixel centres at integers) and depth.
struct ScreenVertex {
  float x, y, z;
};

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

  // Rasterizes the triangles that face the camera (meshes are wound
  // counter-clockwise seen from outside) with a depth test; covered pixels
  // store id_offset + the triangle's index.
  void Draw(const ScreenVertex* vertices, const Eigen::Vector3i* triangles, int num_triangles, int32_t id_offset);

  // The indices of covered pixels, in raster order.
  void CollectCovered(std::vector<int>& pixels) const;

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<float> depth_;
  std::vector<int32_t> triangle_;
  std::vector<float> b1_;
  std::vector<float> b2_;
};

}  // namespace gazedirector
