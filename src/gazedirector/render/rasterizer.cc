#include "gazedirector/render/rasterizer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "gazedirector/util/simd.h"

// AVX2 is the only vector path, also where AVX-512 is available: on an Intel
// Xeon (Emerald Rapids) a 16-lane AVX-512 setup without FillStamps, with
// masked row fills, took about 30% longer to rasterize than this.
#if defined(__AVX2__)
#include <immintrin.h>
#define GAZEDIRECTOR_AVX2 1
#endif

// This file is compiled with -ffp-contract=off: the scalar and vector paths
// must round identically, so that every build renders bit for bit the same.

namespace gazedirector {
namespace {

constexpr int32_t kOne = 1 << kSubpixelBits;
constexpr int32_t kMaxCoordinate = 8192 * kOne;  // farther vertices mean an off-screen model
// Triangles narrower and shorter than this keep every edge value in 32 bits.
constexpr int32_t kSmall = 1024 * kOne;
constexpr float kNearDepth = 1.0f;  // mm
// The buffers run this many elements past their last pixel, so that a row's
// last eight pixels can be loaded and stored whole (AVX2 has no fast masked
// store on AMD).
constexpr std::size_t kPadding = 8;
// Triangles whose pixel boxes are at most this many pixels wide and high are
// filled a batch at a time, one triangle per vector lane (FillStamps).
constexpr int32_t kStampSize = 6;

// Twice the signed area of (a, b, p), positive when p lies to the right of
// a -> b on the y-down screen.
int64_t Edge(const ScreenVertex& a, const ScreenVertex& b, int64_t px, int64_t py) {
  return static_cast<int64_t>(b.y - a.y) * (px - a.x) - static_cast<int64_t>(b.x - a.x) * (py - a.y);
}

// Pixel centres exactly on an edge belong to the triangle only for top and
// left edges, so that no pixel is drawn twice or missed along a shared edge.
// (dx, dy) runs along the edge.
int32_t TopLeftBias(int32_t dx, int32_t dy) { return (dy > 0 || (dy == 0 && dx < 0)) ? 0 : -1; }
int32_t TopLeftBias(const ScreenVertex& a, const ScreenVertex& b) { return TopLeftBias(b.x - a.x, b.y - a.y); }

#if !defined(GAZEDIRECTOR_AVX2)
// Edge() in 32 bits for a small triangle's values; unsigned arithmetic wraps
// where a large triangle's overflow (those are drawn by DrawOne).
int32_t WrappingEdge(int32_t ax, int32_t ay, int32_t bx, int32_t by, int32_t px, int32_t py) {
  return static_cast<int32_t>(static_cast<uint32_t>(by - ay) * static_cast<uint32_t>(px - ax) -
                              static_cast<uint32_t>(bx - ax) * static_cast<uint32_t>(py - ay));
}

// Eight flags of 0 or 1 as the bits of a byte, flag i in bit i: one multiply
// moves every flag into the top byte.
unsigned LaneBits(const int32_t (&flags)[8]) {
  uint8_t bytes[8];
  for (int i = 0; i < 8; ++i) bytes[i] = static_cast<uint8_t>(flags[i]);
  uint64_t packed;
  std::memcpy(&packed, bytes, sizeof(packed));
  return static_cast<unsigned>((packed * 0x0102040810204080ull) >> 56);
}
#endif

int32_t FloorPixel(int32_t v) { return v >> kSubpixelBits; }  // arithmetic shift floors
int32_t CeilPixel(int32_t v) { return -((-v) >> kSubpixelBits); }

}  // namespace

// A small triangle ready to fill: edge values (biased by the top-left rule)
// at its first pixel centre, their steps, and depth interpolation.
struct VisibilityBuffer::Prepared {
  int32_t row[3];
  int32_t step_x[3];
  int32_t step_y[3];
  int32_t bias1, bias2;
  float inverse_area, z0, dz1, dz2;
  int x0, x1, y0, y1;
  int32_t id;
};

// Triangles set up a batch at a time, one per lane, each field an array that
// vector registers store whole. The fills are inlined into the batch loops and
// read their lane's fields from here, so only the fields a fill uses are
// loaded, and no per-triangle copy or call is made.
struct VisibilityBuffer::PreparedBatch {
  static constexpr int kLanes = 8;
  alignas(32) int32_t row0[kLanes], row1[kLanes], row2[kLanes];
  alignas(32) int32_t step_x0[kLanes], step_x1[kLanes], step_x2[kLanes];
  alignas(32) int32_t step_y0[kLanes], step_y1[kLanes], step_y2[kLanes];
  alignas(32) int32_t bias1[kLanes], bias2[kLanes];
  alignas(32) float inverse_area[kLanes], z0[kLanes], dz1[kLanes], dz2[kLanes];
  alignas(32) int32_t x0[kLanes], x1[kLanes], y0[kLanes], y1[kLanes];

  Prepared Lane(int lane, int32_t id) const {
    return {{row0[lane], row1[lane], row2[lane]},
            {step_x0[lane], step_x1[lane], step_x2[lane]},
            {step_y0[lane], step_y1[lane], step_y2[lane]},
            bias1[lane],
            bias2[lane],
            inverse_area[lane],
            z0[lane],
            dz1[lane],
            dz2[lane],
            x0[lane],
            x1[lane],
            y0[lane],
            y1[lane],
            id};
  }
};

void ProjectVertices(const float* xyz, int count, float fx, float fy, float cx, float cy, ScreenVertex* out) {
  int i = 0;
#if defined(GAZEDIRECTOR_AVX2)
  // SnapVertex's arithmetic in the same order, so bit for bit the same.
  const __m256 scale = _mm256_set1_ps(1 << kSubpixelBits);
  const __m256 low = _mm256_set1_ps(-65536.0f), high = _mm256_set1_ps(65536.0f);
  const __m256 half = _mm256_set1_ps(0.5f), minus_half = _mm256_set1_ps(-0.5f), zero = _mm256_setzero_ps();
  auto snap = [&](__m256 pixels) {
    const __m256 s = _mm256_mul_ps(_mm256_min_ps(_mm256_max_ps(pixels, low), high), scale);
    return _mm256_cvttps_epi32(_mm256_add_ps(s, _mm256_blendv_ps(minus_half, half, _mm256_cmp_ps(s, zero, _CMP_GE_OQ))));
  };
  for (; i + 8 <= count; i += 8) {
    // Split by shuffles (gathers are slower).
    const simd::Channels point = simd::LoadTriples(xyz + 3 * i);
    const __m256 x = point.x, y = point.y, z = point.z;
    const __m256 inverse_z = _mm256_div_ps(_mm256_set1_ps(1.0f), z);
    auto pixel = [&](float focal, __m256 v, float principal) {  // focal * v * inverse_z + principal, snapped
      const __m256 scaled = _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(focal), v), inverse_z);
      return _mm256_castsi256_ps(snap(_mm256_add_ps(scaled, _mm256_set1_ps(principal))));
    };
    const __m256 sx = pixel(fx, x, cx), sy = pixel(fy, y, cy);
    // (x, y, z, 0) of eight vertices: the transpose is its own inverse, so
    // the channels come out as records, vertices k | k + 4 in register k.
    const simd::Channels vertex = simd::Transpose(sx, sy, z, zero);
    const __m256 v04 = vertex.x, v15 = vertex.y, v26 = vertex.z, v37 = vertex.w;
    float* o = reinterpret_cast<float*>(out + i);
    _mm256_storeu_ps(o, _mm256_permute2f128_ps(v04, v15, 0x20));       // vertices 0, 1
    _mm256_storeu_ps(o + 8, _mm256_permute2f128_ps(v26, v37, 0x20));   // 2, 3
    _mm256_storeu_ps(o + 16, _mm256_permute2f128_ps(v04, v15, 0x31));  // 4, 5
    _mm256_storeu_ps(o + 24, _mm256_permute2f128_ps(v26, v37, 0x31));  // 6, 7
  }
#endif
  for (; i < count; ++i) {
    const float x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2];
    const float inverse_z = 1.0f / z;
    out[i] = SnapVertex(fx * x * inverse_z + cx, fy * y * inverse_z + cy, z);
  }
}

void VisibilityBuffer::Reset(int width, int height) {
  width_ = width;
  height_ = height;
  const std::size_t n = static_cast<std::size_t>(width) * height + kPadding;
  depth_.assign(n, std::numeric_limits<float>::infinity());
  triangle_.assign(n, -1);
  b1_.resize(n);
  b2_.resize(n);
}

[[gnu::always_inline]] inline void VisibilityBuffer::FillRows(const PreparedBatch& batch, int lane, int32_t id) {
#if defined(GAZEDIRECTOR_AVX2)
  if (vectorized_) {
    FillRowsVectorized(batch, lane, id);
    return;
  }
#endif
  const Prepared p = batch.Lane(lane, id);
  int32_t row0 = p.row[0], row1 = p.row[1], row2 = p.row[2];
  for (int y = p.y0; y <= p.y1; ++y) {
    int32_t w0 = row0, w1 = row1, w2 = row2;
    int pixel = y * width_ + p.x0;
    for (int x = p.x0; x <= p.x1; ++x, ++pixel) {
      if ((w0 | w1 | w2) >= 0) {
        const float b1 = static_cast<float>(w1 - p.bias1) * p.inverse_area;
        const float b2 = static_cast<float>(w2 - p.bias2) * p.inverse_area;
        const float z = p.z0 + b1 * p.dz1 + b2 * p.dz2;
        if (z < depth_[pixel]) {
          depth_[pixel] = z, triangle_[pixel] = p.id, b1_[pixel] = b1, b2_[pixel] = b2;
        }
      }
      w0 += p.step_x[0], w1 += p.step_x[1], w2 += p.step_x[2];
    }
    row0 += p.step_y[0], row1 += p.step_y[1], row2 += p.step_y[2];
  }
}

#if defined(GAZEDIRECTOR_AVX2)
namespace {

// A triangle's interpolation eight pixels at a time, from the lanes' edge
// values: the same arithmetic as FillRows' scalar loop, so bit for bit equal.
struct LaneInterpolation {
  // One triangle in every lane.
  LaneInterpolation(int32_t bias1, int32_t bias2, float inverse_area, float z0, float dz1, float dz2)
      : LaneInterpolation(_mm256_set1_epi32(bias1), _mm256_set1_epi32(bias2), _mm256_set1_ps(inverse_area),
                          _mm256_set1_ps(z0), _mm256_set1_ps(dz1), _mm256_set1_ps(dz2)) {}
  // A triangle per lane (FillStamps).
  LaneInterpolation(__m256i bias1, __m256i bias2, __m256 inverse_area, __m256 z0, __m256 dz1, __m256 dz2)
      : unbias1(bias1), unbias2(bias2), inverse(inverse_area), z0(z0), dz1(dz1), dz2(dz2) {}

  // All ones where the pixel centre is inside (every edge value >= 0).
  static __m256i Inside(__m256i w0, __m256i w1, __m256i w2) {
    return _mm256_cmpgt_epi32(_mm256_or_si256(_mm256_or_si256(w0, w1), w2), _mm256_set1_epi32(-1));
  }
  __m256 B1(__m256i w1) const { return _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(w1, unbias1)), inverse); }
  __m256 B2(__m256i w2) const { return _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(w2, unbias2)), inverse); }
  __m256 Depth(__m256 b1, __m256 b2) const {
    return _mm256_add_ps(_mm256_add_ps(z0, _mm256_mul_ps(b1, dz1)), _mm256_mul_ps(b2, dz2));
  }

  __m256i unbias1, unbias2;
  __m256 inverse, z0, dz1, dz2;
};

}  // namespace

// Eight pixels of a row at a time.
[[gnu::always_inline]] inline void VisibilityBuffer::FillRowsVectorized(const PreparedBatch& batch, int lane, int32_t id) {
  const Prepared p = batch.Lane(lane, id);
  int32_t row0 = p.row[0], row1 = p.row[1], row2 = p.row[2];
  const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i lane_x0 = _mm256_mullo_epi32(lanes, _mm256_set1_epi32(p.step_x[0]));
  const __m256i lane_x1 = _mm256_mullo_epi32(lanes, _mm256_set1_epi32(p.step_x[1]));
  const __m256i lane_x2 = _mm256_mullo_epi32(lanes, _mm256_set1_epi32(p.step_x[2]));
  const __m256i eight_x0 = _mm256_set1_epi32(8 * p.step_x[0]), eight_x1 = _mm256_set1_epi32(8 * p.step_x[1]),
                eight_x2 = _mm256_set1_epi32(8 * p.step_x[2]);
  const LaneInterpolation lerp(p.bias1, p.bias2, p.inverse_area, p.z0, p.dz1, p.dz2);
  const __m256i ids = _mm256_set1_epi32(p.id);
  // AVX2: whole eight-pixel stores of the old values blended with the new
  // ones (the buffers' padding keeps the last row's in bounds).
  if (p.x1 - p.x0 < 4 && width_ >= 4) {
    FillRowPairs(batch, lane, id);
    return;
  }
  for (int y = p.y0; y <= p.y1; ++y) {
    __m256i w0 = _mm256_add_epi32(_mm256_set1_epi32(row0), lane_x0);
    __m256i w1 = _mm256_add_epi32(_mm256_set1_epi32(row1), lane_x1);
    __m256i w2 = _mm256_add_epi32(_mm256_set1_epi32(row2), lane_x2);
    const int row_start = y * width_;
    for (int x = p.x0; x <= p.x1; x += 8) {
      const __m256i in_row = _mm256_cmpgt_epi32(_mm256_set1_epi32(p.x1 - x + 1), lanes);
      const __m256i inside = _mm256_and_si256(in_row, LaneInterpolation::Inside(w0, w1, w2));
      if (!_mm256_testz_si256(inside, inside)) {
        const __m256 b1 = lerp.B1(w1), b2 = lerp.B2(w2), z = lerp.Depth(b1, b2);
        float* depth = depth_.data() + row_start + x;
        const __m256 old_depth = _mm256_loadu_ps(depth);
        const __m256 nearer = _mm256_and_ps(_mm256_castsi256_ps(inside), _mm256_cmp_ps(z, old_depth, _CMP_LT_OQ));
        if (!_mm256_testz_ps(nearer, nearer)) {
          _mm256_storeu_ps(depth, _mm256_blendv_ps(old_depth, z, nearer));
          float* ids_out = reinterpret_cast<float*>(triangle_.data() + row_start + x);
          _mm256_storeu_ps(ids_out, _mm256_blendv_ps(_mm256_loadu_ps(ids_out), _mm256_castsi256_ps(ids), nearer));
          float* b1_out = b1_.data() + row_start + x;
          _mm256_storeu_ps(b1_out, _mm256_blendv_ps(_mm256_loadu_ps(b1_out), b1, nearer));
          float* b2_out = b2_.data() + row_start + x;
          _mm256_storeu_ps(b2_out, _mm256_blendv_ps(_mm256_loadu_ps(b2_out), b2, nearer));
        }
      }
      w0 = _mm256_add_epi32(w0, eight_x0), w1 = _mm256_add_epi32(w1, eight_x1), w2 = _mm256_add_epi32(w2, eight_x2);
    }
    row0 += p.step_y[0], row1 += p.step_y[1], row2 += p.step_y[2];
  }
}
#endif

#if defined(GAZEDIRECTOR_AVX2)
namespace {

// Four pixels of each of two rows in one register; `hi` may equal `lo` (a
// lone last row), and is stored first so that `lo`'s values win.
__m256 LoadRows(const float* lo, const float* hi) {
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(lo)), _mm_loadu_ps(hi), 1);
}
void BlendRows(float* lo, float* hi, __m256 values, __m256 mask) {
  const __m256 blended = _mm256_blendv_ps(LoadRows(lo, hi), values, mask);
  _mm_storeu_ps(hi, _mm256_extractf128_ps(blended, 1));
  _mm_storeu_ps(lo, _mm256_castps256_ps128(blended));
}

}  // namespace

// A triangle at most four pixels wide (at the scale of a fit, most of those
// too tall for FillStamps) takes two rows per eight lanes: half the
// iterations of FillRowsVectorized.
[[gnu::always_inline]] inline void VisibilityBuffer::FillRowPairs(const PreparedBatch& batch, int lane, int32_t id) {
  const Prepared p = batch.Lane(lane, id);
  const __m256i column = _mm256_setr_epi32(0, 1, 2, 3, 0, 1, 2, 3);
  const __m256i upper = _mm256_setr_epi32(-1, -1, -1, -1, 0, 0, 0, 0), lower = _mm256_xor_si256(upper, _mm256_set1_epi32(-1));
  auto start = [&](int k) {
    return _mm256_add_epi32(_mm256_add_epi32(_mm256_set1_epi32(p.row[k]), _mm256_mullo_epi32(column, _mm256_set1_epi32(p.step_x[k]))),
                            _mm256_and_si256(lower, _mm256_set1_epi32(p.step_y[k])));
  };
  __m256i w0 = start(0), w1 = start(1), w2 = start(2);
  const __m256i down0 = _mm256_set1_epi32(2 * p.step_y[0]), down1 = _mm256_set1_epi32(2 * p.step_y[1]),
                down2 = _mm256_set1_epi32(2 * p.step_y[2]);
  const LaneInterpolation lerp(p.bias1, p.bias2, p.inverse_area, p.z0, p.dz1, p.dz2);
  const __m256 ids = _mm256_castsi256_ps(_mm256_set1_epi32(p.id));
  const __m256i in_box = _mm256_cmpgt_epi32(_mm256_set1_epi32(p.x1 - p.x0 + 1), column);
  for (int y = p.y0; y <= p.y1; y += 2) {
    const bool pair = y < p.y1;
    const __m256i valid = pair ? in_box : _mm256_and_si256(in_box, upper);
    const __m256i inside = _mm256_and_si256(valid, LaneInterpolation::Inside(w0, w1, w2));
    if (!_mm256_testz_si256(inside, inside)) {
      const __m256 b1 = lerp.B1(w1), b2 = lerp.B2(w2), z = lerp.Depth(b1, b2);
      const std::size_t lo = static_cast<std::size_t>(y) * width_ + p.x0, hi = pair ? lo + width_ : lo;
      const __m256 nearer = _mm256_and_ps(_mm256_castsi256_ps(inside),
                                          _mm256_cmp_ps(z, LoadRows(depth_.data() + lo, depth_.data() + hi), _CMP_LT_OQ));
      if (!_mm256_testz_ps(nearer, nearer)) {
        BlendRows(depth_.data() + lo, depth_.data() + hi, z, nearer);
        float* triangles = reinterpret_cast<float*>(triangle_.data());
        BlendRows(triangles + lo, triangles + hi, ids, nearer);
        BlendRows(b1_.data() + lo, b1_.data() + hi, b1, nearer);
        BlendRows(b2_.data() + lo, b2_.data() + hi, b2, nearer);
      }
    }
    w0 = _mm256_add_epi32(w0, down0), w1 = _mm256_add_epi32(w1, down1), w2 = _mm256_add_epi32(w2, down2);
  }
}
#endif

#if defined(GAZEDIRECTOR_AVX2)
// The batch's small triangles among `lanes` (boxes up to kStampSize pixels
// wide and high), eight at once, one per lane: each step tests the pixel at
// the same offset in every lane's box. A triangle of a few pixels leaves most
// of a row-wise fill's lanes idle; here the lanes are triangles, so they stay
// busy. The pixels found inside are written one by one, each with its own
// depth test, so two triangles of the batch may cover the same pixel. The
// arithmetic is FillRows', so the values are bit for bit the same; the order
// of the writes differs from one triangle after another, which matters only
// where two triangles reach a pixel centre at exactly the same depth. Returns
// the lanes it filled.
unsigned VisibilityBuffer::FillStamps(const PreparedBatch& p, unsigned lanes, int32_t first_id) {
  auto load = [](const int32_t* field) { return _mm256_load_si256(reinterpret_cast<const __m256i*>(field)); };
  const __m256i x0 = load(p.x0), y0 = load(p.y0);
  const __m256i columns = _mm256_sub_epi32(load(p.x1), x0), rows = _mm256_sub_epi32(load(p.y1), y0);  // box size - 1
  const __m256i too_big = _mm256_or_si256(_mm256_cmpgt_epi32(columns, _mm256_set1_epi32(kStampSize - 1)),
                                          _mm256_cmpgt_epi32(rows, _mm256_set1_epi32(kStampSize - 1)));
  lanes &= ~static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(too_big)));
  if (lanes == 0) return 0;
  const __m256i lane_bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  const __m256i active = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(lanes)), lane_bit), lane_bit);
  // The largest box among the active lanes (each at least 0 wide and high).
  auto largest = [&](__m256i sizes) {
    __m128i m = _mm_max_epi32(_mm256_castsi256_si128(sizes), _mm256_extracti128_si256(sizes, 1));
    m = _mm_max_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtsi128_si32(_mm_max_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 3, 0, 1))));
  };
  const int max_columns = largest(_mm256_and_si256(columns, active)), max_rows = largest(_mm256_and_si256(rows, active));
  const __m256i first_pixel = _mm256_add_epi32(_mm256_mullo_epi32(y0, _mm256_set1_epi32(width_)), x0);
  const __m256i step_x0 = load(p.step_x0), step_x1 = load(p.step_x1), step_x2 = load(p.step_x2);
  const __m256i step_y0 = load(p.step_y0), step_y1 = load(p.step_y1), step_y2 = load(p.step_y2);
  const LaneInterpolation lerp(load(p.bias1), load(p.bias2), _mm256_load_ps(p.inverse_area), _mm256_load_ps(p.z0),
                               _mm256_load_ps(p.dz1), _mm256_load_ps(p.dz2));
  alignas(32) float depths[8], b1s[8], b2s[8];
  alignas(32) int32_t pixels[8];
  float* const depth = depth_.data();
  int32_t* const triangle = triangle_.data();
  float* const b1_out = b1_.data();
  float* const b2_out = b2_.data();
  __m256i row0 = load(p.row0), row1 = load(p.row1), row2 = load(p.row2);
  for (int dy = 0; dy <= max_rows; ++dy) {
    // The active lanes whose box has row dy, and then column dx.
    const __m256i valid_row = _mm256_andnot_si256(_mm256_cmpgt_epi32(_mm256_set1_epi32(dy), rows), active);
    __m256i w0 = row0, w1 = row1, w2 = row2;
    for (int dx = 0; dx <= max_columns; ++dx) {
      const __m256i valid = _mm256_andnot_si256(_mm256_cmpgt_epi32(_mm256_set1_epi32(dx), columns), valid_row);
      const __m256i inside = _mm256_and_si256(valid, LaneInterpolation::Inside(w0, w1, w2));
      unsigned hits = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(inside)));
      if (hits != 0) {
        const __m256 b1 = lerp.B1(w1), b2 = lerp.B2(w2);
        _mm256_store_ps(depths, lerp.Depth(b1, b2));
        _mm256_store_ps(b1s, b1);
        _mm256_store_ps(b2s, b2);
        _mm256_store_si256(reinterpret_cast<__m256i*>(pixels),
                           _mm256_add_epi32(first_pixel, _mm256_set1_epi32(dy * width_ + dx)));
        for (; hits != 0; hits &= hits - 1) {
          const int lane = __builtin_ctz(hits);
          const int pixel = pixels[lane];
          if (depths[lane] < depth[pixel]) {
            depth[pixel] = depths[lane], triangle[pixel] = first_id + lane, b1_out[pixel] = b1s[lane], b2_out[pixel] = b2s[lane];
          }
        }
      }
      w0 = _mm256_add_epi32(w0, step_x0), w1 = _mm256_add_epi32(w1, step_x1), w2 = _mm256_add_epi32(w2, step_x2);
    }
    row0 = _mm256_add_epi32(row0, step_y0), row1 = _mm256_add_epi32(row1, step_y1), row2 = _mm256_add_epi32(row2, step_y2);
  }
  return lanes;
}
#endif

// A triangle of any size (up to the coordinate limit), with 64-bit edge values.
void VisibilityBuffer::FillLarge(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c, int64_t area,
                                 int x0, int x1, int y0, int y1, int32_t id) {
  const float inverse_area = 1.0f / static_cast<float>(area);
  const int64_t bias0 = TopLeftBias(b, c), bias1 = TopLeftBias(c, a), bias2 = TopLeftBias(a, b);
  const int64_t px = static_cast<int64_t>(x0) * kOne, py = static_cast<int64_t>(y0) * kOne;
  int64_t row0 = Edge(b, c, px, py) + bias0, row1 = Edge(c, a, px, py) + bias1, row2 = Edge(a, b, px, py) + bias2;
  const int64_t step_x0 = static_cast<int64_t>(c.y - b.y) * kOne, step_x1 = static_cast<int64_t>(a.y - c.y) * kOne,
                step_x2 = static_cast<int64_t>(b.y - a.y) * kOne;
  const int64_t step_y0 = static_cast<int64_t>(b.x - c.x) * kOne, step_y1 = static_cast<int64_t>(c.x - a.x) * kOne,
                step_y2 = static_cast<int64_t>(a.x - b.x) * kOne;
  const float dz1 = b.z - a.z, dz2 = c.z - a.z;
  for (int y = y0; y <= y1; ++y) {
    int64_t w0 = row0, w1 = row1, w2 = row2;
    int pixel = y * width_ + x0;
    for (int x = x0; x <= x1; ++x, ++pixel) {
      if ((w0 | w1 | w2) >= 0) {
        const float b1 = static_cast<float>(w1 - bias1) * inverse_area;
        const float b2 = static_cast<float>(w2 - bias2) * inverse_area;
        const float z = a.z + b1 * dz1 + b2 * dz2;
        if (z < depth_[pixel]) {
          depth_[pixel] = z, triangle_[pixel] = id, b1_[pixel] = b1, b2_[pixel] = b2;
        }
      }
      w0 += step_x0, w1 += step_x1, w2 += step_x2;
    }
    row0 += step_y0, row1 += step_y1, row2 += step_y2;
  }
}

void VisibilityBuffer::Draw(const ScreenVertex* vertices, const Eigen::Vector3i* triangles, int num_triangles,
                            int32_t id_offset) {
  Draw(vertices, triangles, num_triangles, id_offset, Eigen::Vector4i(0, 0, width_ - 1, height_ - 1));
}

void VisibilityBuffer::Draw(const ScreenVertex* vertices, const Eigen::Vector3i* triangles, int num_triangles,
                            int32_t id_offset, const Eigen::Vector4i& clip_window) {
  const Eigen::Vector4i clip(std::max(0, clip_window[0]), std::max(0, clip_window[1]),
                             std::min(width_ - 1, clip_window[2]), std::min(height_ - 1, clip_window[3]));
  if (clip[0] > clip[2] || clip[1] > clip[3]) return;
  if (vectorized_) {
    DrawBatches(vertices, triangles, num_triangles, id_offset, clip);
    return;
  }
  for (int t = 0; t < num_triangles; ++t) DrawOne(vertices, triangles[t], id_offset + t, clip);
}

#if defined(GAZEDIRECTOR_AVX2)
namespace {

// One corner of eight triangles, a lane each.
struct Corners {
  __m256i x, y;
  __m256 z;
};

// Each vertex read by one vector load, the eight transposed into x, y and z
// (lanes past `count` repeat the last triangle; a full batch, kFull, needs no
// clamping of the lane index).
template <bool kFull>
[[gnu::always_inline]] inline Corners GatherCorner(const ScreenVertex* vertices, const Eigen::Vector3i* triangles,
                                                   int count, int corner) {
  const int last = kFull ? 7 : count - 1;
  auto vertex = [&](int i) {
    return _mm_load_ps(reinterpret_cast<const float*>(vertices + triangles[std::min(i, last)][corner]));
  };
  // Rows: lanes (i, i + 4) of each register hold vertices i and i + 4.
  const __m256 v0 = _mm256_set_m128(vertex(4), vertex(0)), v1 = _mm256_set_m128(vertex(5), vertex(1));
  const __m256 v2 = _mm256_set_m128(vertex(6), vertex(2)), v3 = _mm256_set_m128(vertex(7), vertex(3));
  const simd::Channels xyz = simd::Transpose(v0, v1, v2, v3);
  return {_mm256_castps_si256(xyz.x), _mm256_castps_si256(xyz.y), xyz.z};
}

// Twice the signed area of (a, b, p) in wrapping 32-bit lanes (as the scalar
// setup's WrappingEdge).
__m256i WrappingEdges(__m256i ax, __m256i ay, __m256i bx, __m256i by, __m256i px, __m256i py) {
  return _mm256_sub_epi32(_mm256_mullo_epi32(_mm256_sub_epi32(by, ay), _mm256_sub_epi32(px, ax)),
                          _mm256_mullo_epi32(_mm256_sub_epi32(bx, ax), _mm256_sub_epi32(py, ay)));
}

// TopLeftBias of eight edges running (dx, dy).
__m256i TopLeftBiases(__m256i dx, __m256i dy) {
  const __m256i zero = _mm256_setzero_si256();
  const __m256i top_left = _mm256_or_si256(_mm256_cmpgt_epi32(dy, zero),
                                           _mm256_and_si256(_mm256_cmpeq_epi32(dy, zero), _mm256_cmpgt_epi32(zero, dx)));
  return _mm256_xor_si256(top_left, _mm256_set1_epi32(-1));
}

}  // namespace
#endif

// Eight triangles at a time: their culling, clipping and edge setup are
// branch-free (in vector registers with AVX2, else a loop over the lanes);
// the survivors are then filled: with AVX2 the small ones together by
// FillStamps, the rest one by one in order, large triangles by DrawOne.
void VisibilityBuffer::DrawBatches(const ScreenVertex* vertices, const Eigen::Vector3i* triangles, int num_triangles,
                                   int32_t id_offset, const Eigen::Vector4i& clip) {
  constexpr int kLanes = PreparedBatch::kLanes;
  const int32_t left = clip[0] * kOne, top = clip[1] * kOne, right = clip[2] * kOne, bottom = clip[3] * kOne;
  const int32_t clip_x0 = clip[0], clip_y0 = clip[1], clip_x1 = clip[2], clip_y1 = clip[3];
  PreparedBatch p;
  for (int first = 0; first < num_triangles; first += kLanes) {
    const int count = std::min(kLanes, num_triangles - first);
    // Lanes past the end repeat the last triangle and are never drawn.
    unsigned fill_bits = 0, large_bits = 0;
#if defined(GAZEDIRECTOR_AVX2)
    // The same arithmetic as the scalar loop after #else, lane for lane.
    const bool full = count == kLanes;
    auto gather = [&](int corner) {
      return full ? GatherCorner<true>(vertices, triangles + first, count, corner)
                  : GatherCorner<false>(vertices, triangles + first, count, corner);
    };
    const Corners a = gather(0), b = gather(1), c = gather(2);
    auto at_least = [](__m256i v, int32_t bound) { return _mm256_cmpgt_epi32(v, _mm256_set1_epi32(bound - 1)); };
    auto at_most = [](__m256i v, int32_t bound) { return _mm256_cmpgt_epi32(_mm256_set1_epi32(bound + 1), v); };
    auto bits = [](__m256i mask) { return static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(mask))); };
    const __m256i min_x = _mm256_min_epi32(a.x, _mm256_min_epi32(b.x, c.x));
    const __m256i max_x = _mm256_max_epi32(a.x, _mm256_max_epi32(b.x, c.x));
    const __m256i min_y = _mm256_min_epi32(a.y, _mm256_min_epi32(b.y, c.y));
    const __m256i max_y = _mm256_max_epi32(a.y, _mm256_max_epi32(b.y, c.y));
    const unsigned on_window = bits(_mm256_and_si256(_mm256_and_si256(at_least(max_x, left), at_least(max_y, top)),
                                                     _mm256_and_si256(at_most(min_x, right), at_most(min_y, bottom))));
    const __m256i near_coordinates =
        _mm256_and_si256(_mm256_and_si256(at_least(min_x, -kMaxCoordinate), at_least(min_y, -kMaxCoordinate)),
                         _mm256_and_si256(at_most(max_x, kMaxCoordinate), at_most(max_y, kMaxCoordinate)));
    const unsigned small = bits(_mm256_and_si256(
        near_coordinates, _mm256_and_si256(at_most(_mm256_sub_epi32(max_x, min_x), kSmall - 1),
                                           at_most(_mm256_sub_epi32(max_y, min_y), kSmall - 1))));
    const __m256i area = WrappingEdges(a.x, a.y, b.x, b.y, c.x, c.y);
    const __m256 near = _mm256_set1_ps(kNearDepth);
    const unsigned in_front =
        bits(at_least(area, 1)) & static_cast<unsigned>(_mm256_movemask_ps(_mm256_and_ps(
                                      _mm256_and_ps(_mm256_cmp_ps(a.z, near, _CMP_GE_OQ), _mm256_cmp_ps(b.z, near, _CMP_GE_OQ)),
                                      _mm256_cmp_ps(c.z, near, _CMP_GE_OQ))));
    // CeilPixel and FloorPixel, clipped.
    const __m256i zero = _mm256_setzero_si256();
    auto ceil_pixel = [&](__m256i v) { return _mm256_sub_epi32(zero, _mm256_srai_epi32(_mm256_sub_epi32(zero, v), kSubpixelBits)); };
    const __m256i x0 = _mm256_max_epi32(_mm256_set1_epi32(clip_x0), ceil_pixel(min_x));
    const __m256i x1 = _mm256_min_epi32(_mm256_set1_epi32(clip_x1), _mm256_srai_epi32(max_x, kSubpixelBits));
    const __m256i y0 = _mm256_max_epi32(_mm256_set1_epi32(clip_y0), ceil_pixel(min_y));
    const __m256i y1 = _mm256_min_epi32(_mm256_set1_epi32(clip_y1), _mm256_srai_epi32(max_y, kSubpixelBits));
    const unsigned box = ~bits(_mm256_or_si256(_mm256_cmpgt_epi32(x0, x1), _mm256_cmpgt_epi32(y0, y1))) & 0xFFu;
    fill_bits = on_window & small & in_front & box;
    large_bits = on_window & ~small & 0xFFu;
    const __m256i px = _mm256_slli_epi32(x0, kSubpixelBits), py = _mm256_slli_epi32(y0, kSubpixelBits);
    const __m256i bias0 = TopLeftBiases(_mm256_sub_epi32(c.x, b.x), _mm256_sub_epi32(c.y, b.y));
    const __m256i bias1 = TopLeftBiases(_mm256_sub_epi32(a.x, c.x), _mm256_sub_epi32(a.y, c.y));
    const __m256i bias2 = TopLeftBiases(_mm256_sub_epi32(b.x, a.x), _mm256_sub_epi32(b.y, a.y));
    auto store = [](int32_t* field, __m256i v) { _mm256_store_si256(reinterpret_cast<__m256i*>(field), v); };
    store(p.bias1, bias1);
    store(p.bias2, bias2);
    store(p.row0, _mm256_add_epi32(WrappingEdges(b.x, b.y, c.x, c.y, px, py), bias0));
    store(p.row1, _mm256_add_epi32(WrappingEdges(c.x, c.y, a.x, a.y, px, py), bias1));
    store(p.row2, _mm256_add_epi32(WrappingEdges(a.x, a.y, b.x, b.y, px, py), bias2));
    store(p.step_x0, _mm256_slli_epi32(_mm256_sub_epi32(c.y, b.y), kSubpixelBits));
    store(p.step_x1, _mm256_slli_epi32(_mm256_sub_epi32(a.y, c.y), kSubpixelBits));
    store(p.step_x2, _mm256_slli_epi32(_mm256_sub_epi32(b.y, a.y), kSubpixelBits));
    store(p.step_y0, _mm256_slli_epi32(_mm256_sub_epi32(b.x, c.x), kSubpixelBits));
    store(p.step_y1, _mm256_slli_epi32(_mm256_sub_epi32(c.x, a.x), kSubpixelBits));
    store(p.step_y2, _mm256_slli_epi32(_mm256_sub_epi32(a.x, b.x), kSubpixelBits));
    _mm256_store_ps(p.inverse_area, _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_cvtepi32_ps(area)));
    _mm256_store_ps(p.z0, a.z);
    _mm256_store_ps(p.dz1, _mm256_sub_ps(b.z, a.z));
    _mm256_store_ps(p.dz2, _mm256_sub_ps(c.z, a.z));
    store(p.x0, x0), store(p.x1, x1), store(p.y0, y0), store(p.y1, y1);
#else
    alignas(32) int32_t fill[kLanes], large[kLanes];  // 0 or 1
    for (int i = 0; i < kLanes; ++i) {
      const Eigen::Vector3i& t = triangles[first + std::min(i, count - 1)];
      const ScreenVertex &a = vertices[t[0]], &b = vertices[t[1]], &c = vertices[t[2]];
      const int32_t min_x = std::min({a.x, b.x, c.x}), max_x = std::max({a.x, b.x, c.x});
      const int32_t min_y = std::min({a.y, b.y, c.y}), max_y = std::max({a.y, b.y, c.y});
      const bool on_window = (max_x >= left) & (max_y >= top) & (min_x <= right) & (min_y <= bottom);
      const bool small = (max_x - min_x < kSmall) & (max_y - min_y < kSmall) & (min_x >= -kMaxCoordinate) &
                         (min_y >= -kMaxCoordinate) & (max_x <= kMaxCoordinate) & (max_y <= kMaxCoordinate);
      const int32_t area = WrappingEdge(a.x, a.y, b.x, b.y, c.x, c.y);
      const bool in_front = (area > 0) & (a.z >= kNearDepth) & (b.z >= kNearDepth) & (c.z >= kNearDepth);
      const int32_t x0 = std::max(clip_x0, CeilPixel(min_x)), x1 = std::min(clip_x1, FloorPixel(max_x));
      const int32_t y0 = std::max(clip_y0, CeilPixel(min_y)), y1 = std::min(clip_y1, FloorPixel(max_y));
      fill[i] = on_window & small & in_front & (x0 <= x1) & (y0 <= y1);
      large[i] = on_window & !small;
      const int32_t px = x0 * kOne, py = y0 * kOne;
      p.bias1[i] = TopLeftBias(a.x - c.x, a.y - c.y);
      p.bias2[i] = TopLeftBias(b.x - a.x, b.y - a.y);
      p.row0[i] = WrappingEdge(b.x, b.y, c.x, c.y, px, py) + TopLeftBias(c.x - b.x, c.y - b.y);
      p.row1[i] = WrappingEdge(c.x, c.y, a.x, a.y, px, py) + p.bias1[i];
      p.row2[i] = WrappingEdge(a.x, a.y, b.x, b.y, px, py) + p.bias2[i];
      p.step_x0[i] = (c.y - b.y) * kOne, p.step_x1[i] = (a.y - c.y) * kOne, p.step_x2[i] = (b.y - a.y) * kOne;
      p.step_y0[i] = (b.x - c.x) * kOne, p.step_y1[i] = (c.x - a.x) * kOne, p.step_y2[i] = (a.x - b.x) * kOne;
      p.inverse_area[i] = 1.0f / static_cast<float>(area);
      p.z0[i] = a.z, p.dz1[i] = b.z - a.z, p.dz2[i] = c.z - a.z;
      p.x0[i] = x0, p.x1[i] = x1, p.y0[i] = y0, p.y1[i] = y1;
    }
    fill_bits = LaneBits(fill), large_bits = LaneBits(large);
#endif
    // The lanes to draw as bits, walked in order (a branch per lane mispredicts).
    const unsigned in_batch = (1u << count) - 1;
    unsigned todo = (fill_bits | large_bits) & in_batch;
#if defined(GAZEDIRECTOR_AVX2)
    todo &= ~FillStamps(p, fill_bits & in_batch, id_offset + first);
#endif
    for (; todo != 0; todo &= todo - 1) {
      const int lane = __builtin_ctz(todo);
      const int32_t id = id_offset + first + lane;
      if (large_bits >> lane & 1) {
        DrawOne(vertices, triangles[first + lane], id, clip);
      } else {
        FillRows(p, lane, id);
      }
    }
  }
}

void VisibilityBuffer::DrawOne(const ScreenVertex* vertices, const Eigen::Vector3i& triangle, int32_t id,
                               const Eigen::Vector4i& clip) {
  const ScreenVertex& a = vertices[triangle[0]];
  const ScreenVertex& b = vertices[triangle[1]];
  const ScreenVertex& c = vertices[triangle[2]];
  // Off-screen triangles first: the cheapest test.
  const int32_t min_x = std::min({a.x, b.x, c.x}), max_x = std::max({a.x, b.x, c.x});
  const int32_t min_y = std::min({a.y, b.y, c.y}), max_y = std::max({a.y, b.y, c.y});
  if (max_x < clip[0] * kOne || max_y < clip[1] * kOne || min_x > clip[2] * kOne || min_y > clip[3] * kOne) return;
  // Meshes are counter-clockwise seen from outside; on a y-down screen a
  // triangle facing the camera then has Edge(a, b, c) > 0. Others face away.
  const int64_t area = Edge(a, b, c.x, c.y);
  if (area <= 0) return;
  if (a.z < kNearDepth || b.z < kNearDepth || c.z < kNearDepth) return;
  if (min_x < -kMaxCoordinate || min_y < -kMaxCoordinate || max_x > kMaxCoordinate || max_y > kMaxCoordinate) return;
  // The pixel centres inside the snapped triangle's bounding box.
  const int x0 = std::max(clip[0], CeilPixel(min_x)), x1 = std::min(clip[2], FloorPixel(max_x));
  const int y0 = std::max(clip[1], CeilPixel(min_y)), y1 = std::min(clip[3], FloorPixel(max_y));
  if (x0 > x1 || y0 > y1) return;
  if (max_x - min_x >= kSmall || max_y - min_y >= kSmall) {
    FillLarge(a, b, c, area, x0, x1, y0, y1, id);
    return;
  }
  PreparedBatch p;
  const int64_t px = static_cast<int64_t>(x0) * kOne, py = static_cast<int64_t>(y0) * kOne;
  p.bias1[0] = TopLeftBias(c, a), p.bias2[0] = TopLeftBias(a, b);
  p.row0[0] = static_cast<int32_t>(Edge(b, c, px, py)) + TopLeftBias(b, c);
  p.row1[0] = static_cast<int32_t>(Edge(c, a, px, py)) + p.bias1[0];
  p.row2[0] = static_cast<int32_t>(Edge(a, b, px, py)) + p.bias2[0];
  p.step_x0[0] = (c.y - b.y) * kOne, p.step_x1[0] = (a.y - c.y) * kOne, p.step_x2[0] = (b.y - a.y) * kOne;
  p.step_y0[0] = (b.x - c.x) * kOne, p.step_y1[0] = (c.x - a.x) * kOne, p.step_y2[0] = (a.x - b.x) * kOne;
  p.inverse_area[0] = 1.0f / static_cast<float>(area);
  p.z0[0] = a.z, p.dz1[0] = b.z - a.z, p.dz2[0] = c.z - a.z;
  p.x0[0] = x0, p.x1[0] = x1, p.y0[0] = y0, p.y1[0] = y1;
  FillRows(p, 0, id);
}

#if defined(GAZEDIRECTOR_AVX2)
namespace {

// For each set of eight lanes (a bit mask), the set lanes in order, then zeros.
struct LeftPack {
  alignas(8) uint8_t lanes[256][8];
  constexpr LeftPack() : lanes{} {
    for (int mask = 0; mask < 256; ++mask) {
      int next = 0;
      for (int lane = 0; lane < 8; ++lane) {
        if (mask >> lane & 1) lanes[mask][next++] = static_cast<uint8_t>(lane);
      }
    }
  }
};
constexpr LeftPack kLeftPack;

}  // namespace
#endif

void VisibilityBuffer::CollectCovered(std::vector<int>& pixels) const {
  pixels.resize(static_cast<std::size_t>(size()));
  int count = 0;
  int i = 0;
#if defined(GAZEDIRECTOR_AVX2)
  // Eight pixels at a time, the covered ones moved to the front by a permutation.
  const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), minus_one = _mm256_set1_epi32(-1);
  for (; vectorized_ && i + 8 <= size(); i += 8) {
    const __m256i ids = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(triangle_.data() + i));
    const int covered = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(ids, minus_one)));
    const __m256i order = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(kLeftPack.lanes[covered])));
    const __m256i indices = _mm256_add_epi32(_mm256_set1_epi32(i), lanes);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(pixels.data() + count), _mm256_permutevar8x32_epi32(indices, order));
    count += __builtin_popcount(covered);
  }
#endif
  for (; i < size(); ++i) {
    pixels[count] = i;
    count += triangle_[i] >= 0;
  }
  pixels.resize(static_cast<std::size_t>(count));
}

}  // namespace gazedirector
