// REFERENCE ONLY: the starter kit leaves this file out (the reference's fast
// path, not code given to students).
// Part 2 (speed): the slab test of a node's two children at once, with SSE.
// Same answer as two calls of slab_test (slab_test.h), about twice as fast:
// the two boxes of a sibling pair sit in one 64-byte line and are tested in
// 4-wide registers, x, y and z in parallel.
#pragma once
#include <cmath>

#include "bvh.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#else
#include "slab_test.h"
#endif

namespace pt {

// A ray prepared for the pair test; `inv` is its reciprocal direction, also
// used for single boxes (the root) with slab_test.
struct PairRay {
  Vec3 inv;
#if defined(__SSE2__)
  __m128 o, inv_d;
#else
  Vec3 o, inv_d;
#endif
  explicit PairRay(const Ray& r) {
    // Direction components of (almost) zero are clamped to +-1e-18, as
    // Embree does, so the reciprocals are finite and 0 * inf never makes a
    // NaN; a ray so close to parallel to a slab behaves as parallel.
    const auto safe_inv = [](float d) { return 1.0f / (std::fabs(d) < 1e-18f ? std::copysign(1e-18f, d) : d); };
    inv = Vec3(safe_inv(r.d.x), safe_inv(r.d.y), safe_inv(r.d.z));
#if defined(__SSE2__)
    // Lane 3 holds the node's first/count integers; it is masked out below.
    o = _mm_setr_ps(r.o.x, r.o.y, r.o.z, 0.0f);
    inv_d = _mm_setr_ps(inv.x, inv.y, inv.z, 0.0f);
#else
    o = r.o;
    inv_d = inv;
#endif
  }
};

// Tests the two children a = nodes[i], b = nodes[i + 1] against the ray's
// interval [t_min, t_max]. Returns bit 0 when a is hit, bit 1 when b is,
// and their entry distances.
inline int slab_test_pair(const BVHNode* pair, const PairRay& ray, float t_min, float t_max, float* t_a,
                          float* t_b) {
#if defined(__SSE2__)
  const float* f = reinterpret_cast<const float*>(pair);
  const __m128 a_lo = _mm_loadu_ps(f), a_hi = _mm_loadu_ps(f + 4);
  const __m128 b_lo = _mm_loadu_ps(f + 8), b_hi = _mm_loadu_ps(f + 12);
  const __m128 a0 = _mm_mul_ps(_mm_sub_ps(a_lo, ray.o), ray.inv_d);
  const __m128 a1 = _mm_mul_ps(_mm_sub_ps(a_hi, ray.o), ray.inv_d);
  const __m128 b0 = _mm_mul_ps(_mm_sub_ps(b_lo, ray.o), ray.inv_d);
  const __m128 b1 = _mm_mul_ps(_mm_sub_ps(b_hi, ray.o), ray.inv_d);
  // Per axis: near = min, far = max of the two plane crossings. Lane 3 is
  // forced to (-inf, +inf) so that it never decides.
  const __m128 xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
  const __m128 w_near = _mm_setr_ps(0, 0, 0, -INFINITY), w_far = _mm_setr_ps(0, 0, 0, INFINITY);
  const __m128 na = _mm_or_ps(_mm_and_ps(_mm_min_ps(a0, a1), xyz), w_near);
  const __m128 fa = _mm_or_ps(_mm_and_ps(_mm_max_ps(a0, a1), xyz), w_far);
  const __m128 nb = _mm_or_ps(_mm_and_ps(_mm_min_ps(b0, b1), xyz), w_near);
  const __m128 fb = _mm_or_ps(_mm_and_ps(_mm_max_ps(b0, b1), xyz), w_far);
  // Horizontal max of the nears and min of the fars, both boxes at once:
  // lanes 0 and 1 end up holding a's and b's values.
  __m128 n = _mm_max_ps(_mm_unpacklo_ps(na, nb), _mm_unpackhi_ps(na, nb));
  n = _mm_max_ps(n, _mm_movehl_ps(n, n));
  __m128 fr = _mm_min_ps(_mm_unpacklo_ps(fa, fb), _mm_unpackhi_ps(fa, fb));
  fr = _mm_min_ps(fr, _mm_movehl_ps(fr, fr));
  n = _mm_max_ps(n, _mm_set1_ps(t_min));
  fr = _mm_min_ps(fr, _mm_set1_ps(t_max));
  const int hit = _mm_movemask_ps(_mm_cmple_ps(n, fr)) & 3;
  alignas(16) float near_out[4];
  _mm_store_ps(near_out, n);
  *t_a = near_out[0];
  *t_b = near_out[1];
  return hit;
#else
  const bool ha = slab_test(pair[0].lo, pair[0].hi, ray.o, ray.inv_d, t_min, t_max, t_a);
  const bool hb = slab_test(pair[1].lo, pair[1].hi, ray.o, ray.inv_d, t_min, t_max, t_b);
  return int(ha) | (int(hb) << 1);
#endif
}

}  // namespace pt
