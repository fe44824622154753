#pragma once

// AVX helpers shared by the model and the renderer: eight records of three or
// four floats moved between their layout in memory and one register per
// channel. Callers keep scalar loops for builds without AVX.

#if defined(__AVX__)
#include <immintrin.h>

namespace gazedirector::simd {

// Eight records' channels, one register each, records 0-3 in the low 128-bit
// lanes and 4-7 in the high.
struct Channels {
  __m256 x, y, z, w;
};

// Eight records of four floats, row k holding record k in its low 128 bits
// and record k + 4 in its high (as _mm256_loadu2_m128 or _mm256_set_m128
// put them), transposed into their four channels.
[[gnu::always_inline]] inline Channels Transpose(__m256 row0, __m256 row1, __m256 row2, __m256 row3) {
  const __m256 low01 = _mm256_unpacklo_ps(row0, row1), low23 = _mm256_unpacklo_ps(row2, row3);      // x0 x1 y0 y1
  const __m256 high01 = _mm256_unpackhi_ps(row0, row1), high23 = _mm256_unpackhi_ps(row2, row3);  // z0 z1 w0 w1
  return {_mm256_shuffle_ps(low01, low23, _MM_SHUFFLE(1, 0, 1, 0)), _mm256_shuffle_ps(low01, low23, _MM_SHUFFLE(3, 2, 3, 2)),
          _mm256_shuffle_ps(high01, high23, _MM_SHUFFLE(1, 0, 1, 0)),
          _mm256_shuffle_ps(high01, high23, _MM_SHUFFLE(3, 2, 3, 2))};
}

// Eight consecutive (x, y, z) triples as three channels (w is left unset).
[[gnu::always_inline]] inline Channels LoadTriples(const float* p) {
  const __m256 m03 = _mm256_loadu2_m128(p + 12, p), m14 = _mm256_loadu2_m128(p + 16, p + 4);  // x0 y0 z0 x1, y1 z1 x2 y2
  const __m256 m25 = _mm256_loadu2_m128(p + 20, p + 8);                                        // z2 x3 y3 z3
  const __m256 xy = _mm256_shuffle_ps(m14, m25, _MM_SHUFFLE(2, 1, 3, 2));  // x2 y2 x3 y3
  const __m256 yz = _mm256_shuffle_ps(m03, m14, _MM_SHUFFLE(1, 0, 2, 1));  // y0 z0 y1 z1
  return {_mm256_shuffle_ps(m03, xy, _MM_SHUFFLE(2, 0, 3, 0)), _mm256_shuffle_ps(yz, xy, _MM_SHUFFLE(3, 1, 2, 0)),
          _mm256_shuffle_ps(yz, m25, _MM_SHUFFLE(3, 0, 3, 1)), _mm256_setzero_ps()};
}

// The inverse of LoadTriples: three channels stored as eight consecutive triples.
[[gnu::always_inline]] inline void StoreTriples(__m256 x, __m256 y, __m256 z, float* out) {
  const __m256 xy = _mm256_shuffle_ps(x, y, _MM_SHUFFLE(2, 0, 2, 0));  // x0 x2 y0 y2
  const __m256 yz = _mm256_shuffle_ps(y, z, _MM_SHUFFLE(3, 1, 3, 1));  // y1 y3 z1 z3
  const __m256 zx = _mm256_shuffle_ps(z, x, _MM_SHUFFLE(3, 1, 2, 0));  // z0 z2 x1 x3
  _mm256_storeu2_m128(out + 12, out, _mm256_shuffle_ps(xy, zx, _MM_SHUFFLE(2, 0, 2, 0)));     // x0 y0 z0 x1
  _mm256_storeu2_m128(out + 16, out + 4, _mm256_shuffle_ps(yz, xy, _MM_SHUFFLE(3, 1, 2, 0)));  // y1 z1 x2 y2
  _mm256_storeu2_m128(out + 20, out + 8, _mm256_shuffle_ps(zx, yz, _MM_SHUFFLE(3, 1, 3, 1)));  // z2 x3 y3 z3
}

}  // namespace gazedirector::simd

#endif
