// Overlap4: whether a box overlaps each of four boxes stored side by side (the minima and maxima of four
// boxes as arrays of four), in one packed compare where SSE is there. The node test of the broad-phase quad
// tree and of the mesh hierarchy. Pure function; any thread.
#pragma once

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include "physics/math/AABB.h"

namespace strata {

/// Bit i set where box i overlaps `box`; the arrays are 16-byte aligned. Inside-out boxes overlap nothing.
inline int OverlapMask4(const float* min_x, const float* min_y, const float* min_z, const float* max_x,
                        const float* max_y, const float* max_z, const AABB& box) {
#if defined(__SSE2__)
  auto axis = [](const float* low, const float* high, float box_low, float box_high) {
    return _mm_and_ps(_mm_cmple_ps(_mm_load_ps(low), _mm_set1_ps(box_high)),
                      _mm_cmple_ps(_mm_set1_ps(box_low), _mm_load_ps(high)));
  };
  const __m128 hit = _mm_and_ps(
      axis(min_x, max_x, box.min.x(), box.max.x()),
      _mm_and_ps(axis(min_y, max_y, box.min.y(), box.max.y()), axis(min_z, max_z, box.min.z(), box.max.z())));
  return _mm_movemask_ps(hit);
#else
  int mask = 0;
  for (int i = 0; i < 4; ++i) {
    const bool hit = (min_x[i] <= box.max.x()) & (box.min.x() <= max_x[i]) & (min_y[i] <= box.max.y()) &
                     (box.min.y() <= max_y[i]) & (min_z[i] <= box.max.z()) & (box.min.z() <= max_z[i]);
    mask |= static_cast<int>(hit) << i;
  }
  return mask;
#endif
}

}  // namespace strata
