#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#if defined(__AVX__)
#include <immintrin.h>
#endif


namespace gazedirector {

// A square float texture with C interleaved channels and a mip chain. Texture
// coordinates have their origin at the bottom left (OpenGL): u right, v up;
// sampling is bilinear with clamping at the edges.
template <int C>
class Texture {
 public:
  Texture() = default;
  explicit Texture(int size) { Resize(size); }

  void Resize(int size) {
    levels_.clear();
    sizes_.clear();
    for (int s = size; s >= 4; s /= 2) {
      sizes_.push_back(s);
      levels_.emplace_back(static_cast<std::size_t>(s) * s * C, 0.0f);
    }
  }

  int size(int level = 0) const { return sizes_[level]; }
  int num_levels() const { return static_cast<int>(sizes_.size()); }
  bool empty() const { return sizes_.empty(); }
  float* data(int level = 0) { return levels_[level].data(); }
  const float* data(int level = 0) const { return levels_[level].data(); }

  // Fills every level below 0 by 2x2 averaging.
  void BuildMips() {
    for (int level = 1; level < num_levels(); ++level) {
      const int s = sizes_[level];
      const int parent = sizes_[level - 1];
      const float* source = levels_[level - 1].data();
      float* target = levels_[level].data();
      for (int y = 0; y < s; ++y) {
        for (int x = 0; x < s; ++x) {
          for (int c = 0; c < C; ++c) {
            const float* p = source + (static_cast<std::size_t>(2 * y) * parent + 2 * x) * C + c;
            target[(static_cast<std::size_t>(y) * s + x) * C + c] = 0.25f * (p[0] + p[C] + p[parent * C] + p[parent * C + C]);
          }
        }
      }
    }
  }

  // The level whose texels are about one pixel when `texels_per_pixel` texels
  // of level 0 cover a pixel.
  int LevelFor(float texels_per_pixel) const {
    int level = 0;
    while (texels_per_pixel > 1.5f && level + 1 < num_levels()) texels_per_pixel *= 0.5f, ++level;
    return level;
  }

  // One mip level, for sampling it many times.
  struct Level {
    const float* texels;
    int size;

    // Where a bilinear sample at (u, v) reads, clamped at the edges: the
    // offset of its top-left texel (in floats) and the weights of the texels
    // right of and below it. LocateMany does the same for many coordinates in
    // a loop the compiler vectorises.
    void Locate(float u, float v, int32_t& offset, float& fx, float& fy) const {
      const float scale = static_cast<float>(size), last = scale - 1.001f;
      // In this operand order a NaN coordinate clamps to 0 instead of reading outside.
      const float x = std::min(last, std::max(0.0f, u * scale - 0.5f));
      const float y = std::min(last, std::max(0.0f, (1.0f - v) * scale - 0.5f));
      const int32_t x0 = static_cast<int32_t>(x), y0 = static_cast<int32_t>(y);
      fx = x - static_cast<float>(x0);
      fy = y - static_cast<float>(y0);
      offset = (y0 * size + x0) * C;
    }
    void LocateMany(const float* u, const float* v, int n, int32_t* offset, float* fx, float* fy) const {
      for (int i = 0; i < n; ++i) Locate(u[i], v[i], offset[i], fx[i], fy[i]);
    }
    // The bilinear sample at a located position; four channels. Down the
    // columns first, so that one 8-float load reads a row's two texels.
    Eigen::Vector4f SampleAt(int32_t offset, float fx, float fy) const {
      static_assert(C == 4);
      const float* row0 = texels + offset;
      const float* row1 = row0 + static_cast<std::ptrdiff_t>(size) * 4;
#if defined(__AVX__)
      const __m256 top = _mm256_loadu_ps(row0), bottom = _mm256_loadu_ps(row1);
      const __m256 down = _mm256_add_ps(top, _mm256_mul_ps(_mm256_set1_ps(fy), _mm256_sub_ps(bottom, top)));
      const __m128 left = _mm256_castps256_ps128(down), right = _mm256_extractf128_ps(down, 1);
      Eigen::Vector4f sample;
      _mm_storeu_ps(sample.data(), _mm_add_ps(left, _mm_mul_ps(_mm_set1_ps(fx), _mm_sub_ps(right, left))));
      return sample;
#else
      using Texel = Eigen::Map<const Eigen::Vector4f>;
      const Eigen::Vector4f left = Texel(row0) + fy * (Texel(row1) - Texel(row0));
      const Eigen::Vector4f right = Texel(row0 + 4) + fy * (Texel(row1 + 4) - Texel(row0 + 4));
      return left + fx * (right - left);
#endif
    }
    Eigen::Vector4f Sample(float u, float v) const {
      int32_t offset;
      float fx, fy;
      Locate(u, v, offset, fx, fy);
      return SampleAt(offset, fx, fy);
    }
  };
  Level level(int index) const { return {levels_[index].data(), sizes_[index]}; }

 private:
  std::vector<int> sizes_;
  std::vector<std::vector<float>> levels_;
};

using RgbaTexture = Texture<4>;  // RGB and a spare channel, for vector loads

}  // namespace gazedirector
