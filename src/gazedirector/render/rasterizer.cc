#include "gazedirector/render/rasterizer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gazedirector {
namespace {

// 4 sub-pixel bits: vertices snap to 1/16 pixel, edge functions are exact
// integers, so shared edges are watertight and every render is bit-for-bit
// reproducible.
constexpr int kSubpixelBits = 4;
constexpr float kSubpixelScale = 1 << kSubpixelBits;
constexpr float kMaxCoordinate = 8192.0f;  // pixels; farther vertices mean an off-screen model
constexpr float kNearDepth = 1.0f;         // mm

struct Fixed {
  int64_t x, y;
};

Fixed Snap(const ScreenVertex& v) {
  return {static_cast<int64_t>(std::lround(v.x * kSubpixelScale)), static_cast<int64_t>(std::lround(v.y * kSubpixelScale))};
}

// Twice the signed area of (a, b, p), positive when p lies to the right of
// a -> b on the y-down screen.
int64_t Edge(const Fixed& a, const Fixed& b, int64_t px, int64_t py) {
  return (b.y - a.y) * (px - a.x) - (b.x - a.x) * (py - a.y);
}

// Pixel centres exactly on an edge belong to the triangle only for top and
// left edges, so that no pixel is drawn twice or missed along a shared edge.
int64_t TopLeftBias(const Fixed& a, const Fixed& b) {
  const int64_t dy = b.y - a.y, dx = b.x - a.x;
  return (dy > 0 || (dy == 0 && dx < 0)) ? 0 : -1;
}

}  // namespace

void VisibilityBuffer::Reset(int width, int height) {
  width_ = width;
  height_ = height;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  depth_.assign(n, std::numeric_limits<float>::infinity());
  triangle_.assign(n, -1);
  b1_.resize(n);
  b2_.resize(n);
}

void VisibilityBuffer::Draw(const ScreenVertex* vertices, const Eigen::Vector3i* triangles, int num_triangles,
                            int32_t id_offset) {
  for (int t = 0; t < num_triangles; ++t) {
    const ScreenVertex& v0 = vertices[triangles[t][0]];
    const ScreenVertex& v1 = vertices[triangles[t][1]];
    const ScreenVertex& v2 = vertices[triangles[t][2]];
    if (v0.z < kNearDepth || v1.z < kNearDepth || v2.z < kNearDepth) continue;
    const float min_x = std::min({v0.x, v1.x, v2.x}), max_x = std::max({v0.x, v1.x, v2.x});
    const float min_y = std::min({v0.y, v1.y, v2.y}), max_y = std::max({v0.y, v1.y, v2.y});
    if (max_x < -1 || max_y < -1 || min_x > width_ || min_y > height_) continue;
    if (min_x < -kMaxCoordinate || min_y < -kMaxCoordinate || max_x > kMaxCoordinate || max_y > kMaxCoordinate) continue;
    const Fixed a = Snap(v0), b = Snap(v1), c = Snap(v2);
    // The bounding box of the snapped triangle in whole pixels, clipped to the
    // target (from the snapped, not the raw, vertices: a pixel centre on a
    // snapped edge must not fall outside the box).
    constexpr int64_t kOne = 1 << kSubpixelBits;
    const auto floor_pixel = [](int64_t v) { return static_cast<int>(v >= 0 ? v / kOne : -((-v + kOne - 1) / kOne)); };
    const auto ceil_pixel = [&](int64_t v) { return -floor_pixel(-v); };
    const int x0 = std::max(0, ceil_pixel(std::min({a.x, b.x, c.x})));
    const int x1 = std::min(width_ - 1, floor_pixel(std::max({a.x, b.x, c.x})));
    const int y0 = std::max(0, ceil_pixel(std::min({a.y, b.y, c.y})));
    const int y1 = std::min(height_ - 1, floor_pixel(std::max({a.y, b.y, c.y})));
    if (x0 > x1 || y0 > y1) continue;

    // Meshes are counter-clockwise seen from outside; on a y-down screen a
    // triangle facing the camera then has (b - a) x (c - a) < 0, that is
    // Edge(a, b, c) > 0. Others face away and are culled.
    const int64_t area = Edge(a, b, c.x, c.y);
    if (area <= 0) continue;
    const float inverse_area = 1.0f / static_cast<float>(area);
    const int64_t bias0 = TopLeftBias(b, c), bias1 = TopLeftBias(c, a), bias2 = TopLeftBias(a, b);
    // Edge values at the first pixel centre and their steps along x and y.
    const int64_t px = static_cast<int64_t>(x0) << kSubpixelBits, py = static_cast<int64_t>(y0) << kSubpixelBits;
    int64_t row0 = Edge(b, c, px, py) + bias0, row1 = Edge(c, a, px, py) + bias1, row2 = Edge(a, b, px, py) + bias2;
    const int64_t step_x0 = (c.y - b.y) << kSubpixelBits, step_x1 = (a.y - c.y) << kSubpixelBits,
                  step_x2 = (b.y - a.y) << kSubpixelBits;
    const int64_t step_y0 = -(c.x - b.x) << kSubpixelBits, step_y1 = -(a.x - c.x) << kSubpixelBits,
                  step_y2 = -(b.x - a.x) << kSubpixelBits;
    const float dz1 = v1.z - v0.z, dz2 = v2.z - v0.z;
    const int32_t id = id_offset + t;
    for (int y = y0; y <= y1; ++y) {
      int64_t w0 = row0, w1 = row1, w2 = row2;
      int pixel = y * width_ + x0;
      for (int x = x0; x <= x1; ++x, ++pixel) {
        if ((w0 | w1 | w2) >= 0) {
          // Undo the bias for exact weights.
          const float b1 = static_cast<float>(w1 - bias1) * inverse_area;
          const float b2 = static_cast<float>(w2 - bias2) * inverse_area;
          const float z = v0.z + b1 * dz1 + b2 * dz2;
          if (z < depth_[pixel]) {
            depth_[pixel] = z;
            triangle_[pixel] = id;
            b1_[pixel] = b1;
            b2_[pixel] = b2;
          }
        }
        w0 += step_x0, w1 += step_x1, w2 += step_x2;
      }
      row0 += step_y0, row1 += step_y1, row2 += step_y2;
    }
  }
}

void VisibilityBuffer::CollectCovered(std::vector<int>& pixels) const {
  pixels.clear();
  for (int i = 0; i < size(); ++i) {
    if (triangle_[i] >= 0) pixels.push_back(i);
  }
}

}  // namespace gazedirector
