#include "gazedirector/render/rasterizer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#if defined(__AVX512F__) && defined(__AVX512VL__)
#include <immintrin.h>
#define GAZEDIRECTOR_AVX512 1
#endif

namespace gazedirector {
namespace {

constexpr int32_t kOne = 1 << kSubpixelBits;
constexpr int32_t kMaxCoordinate = 8192 * kOne;  // farther vertices mean an off-screen model
constexpr float kNearDepth = 1.0f;  // mm

// Twice the signed area of (a, b, p), positive when p lies to the right of
// a -> b on the y-down screen.
int64_t Edge(const ScreenVertex& a, const ScreenVertex& b, int64_t px, int64_t py) {
  return static_cast<int64_t>(b.y - a.y) * (px - a.x) - static_cast<int64_t>(b.x - a.x) * (py - a.y);
}

// Pixel centres exactly on an edge belong to the triangle only for top and
// left edges, so that no pixel is drawn twice or missed along a shared edge.
int64_t TopLeftBias(const ScreenVertex& a, const ScreenVertex& b) {
  const int32_t dy = b.y - a.y, dx = b.x - a.x;
  return (dy > 0 || (dy == 0 && dx < 0)) ? 0 : -1;
}

int32_t FloorPixel(int32_t v) { return v >> kSubpixelBits; }  // arithmetic shift floors
int32_t CeilPixel(int32_t v) { return -((-v) >> kSubpixelBits); }

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

template <typename Int>
void VisibilityBuffer::Fill(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c, int64_t area, int x0,
                            int x1, int y0, int y1, int32_t id) {
  const float inverse_area = 1.0f / static_cast<float>(area);
  const Int bias0 = static_cast<Int>(TopLeftBias(b, c)), bias1 = static_cast<Int>(TopLeftBias(c, a)),
            bias2 = static_cast<Int>(TopLeftBias(a, b));
  // Edge values at the first pixel centre and their steps along x and y.
  const int64_t px = static_cast<int64_t>(x0) * kOne, py = static_cast<int64_t>(y0) * kOne;
  Int row0 = static_cast<Int>(Edge(b, c, px, py)) + bias0;
  Int row1 = static_cast<Int>(Edge(c, a, px, py)) + bias1;
  Int row2 = static_cast<Int>(Edge(a, b, px, py)) + bias2;
  const Int step_x0 = static_cast<Int>(c.y - b.y) * kOne, step_x1 = static_cast<Int>(a.y - c.y) * kOne,
            step_x2 = static_cast<Int>(b.y - a.y) * kOne;
  const Int step_y0 = static_cast<Int>(b.x - c.x) * kOne, step_y1 = static_cast<Int>(c.x - a.x) * kOne,
            step_y2 = static_cast<Int>(a.x - b.x) * kOne;
  const float dz1 = b.z - a.z, dz2 = c.z - a.z;
  for (int y = y0; y <= y1; ++y) {
    Int w0 = row0, w1 = row1, w2 = row2;
    int pixel = y * width_ + x0;
    for (int x = x0; x <= x1; ++x, ++pixel) {
      if ((w0 | w1 | w2) >= 0) {
        // Undo the bias for exact weights.
        const float b1 = static_cast<float>(w1 - bias1) * inverse_area;
        const float b2 = static_cast<float>(w2 - bias2) * inverse_area;
        const float z = a.z + b1 * dz1 + b2 * dz2;
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

#if defined(GAZEDIRECTOR_AVX512)
// Eight pixels of a row at a time with AVX-512 masks (AVX2's masked stores
// are microcoded and slow on AMD): the same integer edge tests and the same
// float arithmetic as the scalar loop, so the results are identical.
template <>
void VisibilityBuffer::Fill<int32_t>(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c, int64_t area,
                                     int x0, int x1, int y0, int y1, int32_t id) {
  const float inverse_area = 1.0f / static_cast<float>(area);
  const int32_t bias0 = static_cast<int32_t>(TopLeftBias(b, c)), bias1 = static_cast<int32_t>(TopLeftBias(c, a)),
                bias2 = static_cast<int32_t>(TopLeftBias(a, b));
  const int64_t px = static_cast<int64_t>(x0) * kOne, py = static_cast<int64_t>(y0) * kOne;
  int32_t row0 = static_cast<int32_t>(Edge(b, c, px, py)) + bias0;
  int32_t row1 = static_cast<int32_t>(Edge(c, a, px, py)) + bias1;
  int32_t row2 = static_cast<int32_t>(Edge(a, b, px, py)) + bias2;
  const int32_t step_x0 = (c.y - b.y) * kOne, step_x1 = (a.y - c.y) * kOne, step_x2 = (b.y - a.y) * kOne;
  const int32_t step_y0 = (b.x - c.x) * kOne, step_y1 = (c.x - a.x) * kOne, step_y2 = (a.x - b.x) * kOne;
  const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i lane_x0 = _mm256_mullo_epi32(lanes, _mm256_set1_epi32(step_x0));
  const __m256i lane_x1 = _mm256_mullo_epi32(lanes, _mm256_set1_epi32(step_x1));
  const __m256i lane_x2 = _mm256_mullo_epi32(lanes, _mm256_set1_epi32(step_x2));
  const __m256i eight_x0 = _mm256_set1_epi32(8 * step_x0), eight_x1 = _mm256_set1_epi32(8 * step_x1),
                eight_x2 = _mm256_set1_epi32(8 * step_x2);
  const __m256i unbias1 = _mm256_set1_epi32(bias1), unbias2 = _mm256_set1_epi32(bias2);
  const __m256 inverse = _mm256_set1_ps(inverse_area);
  const __m256 z0 = _mm256_set1_ps(a.z), dz1 = _mm256_set1_ps(b.z - a.z), dz2 = _mm256_set1_ps(c.z - a.z);
  const __m256i ids = _mm256_set1_epi32(id);
  const __m256i minus_one = _mm256_set1_epi32(-1);
  for (int y = y0; y <= y1; ++y) {
    __m256i w0 = _mm256_add_epi32(_mm256_set1_epi32(row0), lane_x0);
    __m256i w1 = _mm256_add_epi32(_mm256_set1_epi32(row1), lane_x1);
    __m256i w2 = _mm256_add_epi32(_mm256_set1_epi32(row2), lane_x2);
    const int row_start = y * width_;
    for (int x = x0; x <= x1; x += 8) {
      const __mmask8 in_row = static_cast<__mmask8>(x1 - x >= 7 ? 0xFF : (1u << (x1 - x + 1)) - 1);
      const __mmask8 mask = _mm256_mask_cmpgt_epi32_mask(in_row, _mm256_or_si256(_mm256_or_si256(w0, w1), w2), minus_one);
      if (mask != 0) {
        const __m256 b1 = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(w1, unbias1)), inverse);
        const __m256 b2 = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(w2, unbias2)), inverse);
        // a.z + b1 dz1 + b2 dz2, in the scalar loop's order (no fused multiply-add).
        const __m256 z = _mm256_add_ps(_mm256_add_ps(z0, _mm256_mul_ps(b1, dz1)), _mm256_mul_ps(b2, dz2));
        float* depth = depth_.data() + row_start + x;
        const __m256 current = _mm256_maskz_loadu_ps(mask, depth);
        const __mmask8 nearer = _mm256_mask_cmp_ps_mask(mask, z, current, _CMP_LT_OQ);
        if (nearer != 0) {
          _mm256_mask_storeu_ps(depth, nearer, z);
          _mm256_mask_storeu_epi32(triangle_.data() + row_start + x, nearer, ids);
          _mm256_mask_storeu_ps(b1_.data() + row_start + x, nearer, b1);
          _mm256_mask_storeu_ps(b2_.data() + row_start + x, nearer, b2);
        }
      }
      w0 = _mm256_add_epi32(w0, eight_x0), w1 = _mm256_add_epi32(w1, eight_x1), w2 = _mm256_add_epi32(w2, eight_x2);
    }
    row0 += step_y0, row1 += step_y1, row2 += step_y2;
  }
}
#endif

void VisibilityBuffer::Draw(const ScreenVertex* vertices, const Eigen::Vector3i* triangles, int num_triangles,
                            int32_t id_offset) {
  Draw(vertices, triangles, num_triangles, id_offset, Eigen::Vector4i(0, 0, width_ - 1, height_ - 1));
}

void VisibilityBuffer::Draw(const ScreenVertex* vertices, const Eigen::Vector3i* triangles, int num_triangles,
                            int32_t id_offset, const Eigen::Vector4i& clip) {
  const int clip_x0 = std::max(0, clip[0]), clip_y0 = std::max(0, clip[1]);
  const int clip_x1 = std::min(width_ - 1, clip[2]), clip_y1 = std::min(height_ - 1, clip[3]);
  if (clip_x0 > clip_x1 || clip_y0 > clip_y1) return;
  const int32_t left = clip_x0 * kOne, top = clip_y0 * kOne, right = clip_x1 * kOne, bottom = clip_y1 * kOne;
  for (int t = 0; t < num_triangles; ++t) {
    const ScreenVertex& a = vertices[triangles[t][0]];
    const ScreenVertex& b = vertices[triangles[t][1]];
    const ScreenVertex& c = vertices[triangles[t][2]];
    // Off-screen triangles first: the cheapest test.
    const int32_t min_x = std::min({a.x, b.x, c.x}), max_x = std::max({a.x, b.x, c.x});
    const int32_t min_y = std::min({a.y, b.y, c.y}), max_y = std::max({a.y, b.y, c.y});
    if (max_x < left || max_y < top || min_x > right || min_y > bottom) continue;
    // Meshes are counter-clockwise seen from outside; on a y-down screen a
    // triangle facing the camera then has Edge(a, b, c) > 0. Others face away.
    const int64_t area = Edge(a, b, c.x, c.y);
    if (area <= 0) continue;
    if (a.z < kNearDepth || b.z < kNearDepth || c.z < kNearDepth) continue;
    if (min_x < -kMaxCoordinate || min_y < -kMaxCoordinate || max_x > kMaxCoordinate || max_y > kMaxCoordinate) continue;
    // The pixel centres inside the snapped triangle's bounding box.
    const int x0 = std::max(clip_x0, CeilPixel(min_x)), x1 = std::min(clip_x1, FloorPixel(max_x));
    const int y0 = std::max(clip_y0, CeilPixel(min_y)), y1 = std::min(clip_y1, FloorPixel(max_y));
    if (x0 > x1 || y0 > y1) continue;
    // Edge values stay within 32 bits when the triangle spans under 1024 px.
    constexpr int32_t kSmall = 1024 * kOne;
    if (max_x - min_x < kSmall && max_y - min_y < kSmall) {
      Fill<int32_t>(a, b, c, area, x0, x1, y0, y1, id_offset + t);
    } else {
      Fill<int64_t>(a, b, c, area, x0, x1, y0, y1, id_offset + t);
    }
  }
}

void VisibilityBuffer::CollectCovered(std::vector<int>& pixels) const {
  pixels.resize(static_cast<std::size_t>(size()));
  int count = 0;
  for (int i = 0; i < size(); ++i) {
    pixels[count] = i;
    count += triangle_[i] >= 0;
  }
  pixels.resize(static_cast<std::size_t>(count));
}

}  // namespace gazedirector
