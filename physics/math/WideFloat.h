// WideFloat: a fixed number of float lanes processed together, the lane type of the wide contact solver
// (one constraint per lane). It spans two SIMD registers, 16 lanes with AVX (STRATA_ARCH=x86-64-v3) and 8
// with SSE on plain x86-64 (a loop elsewhere): the solver's per-point update is a long chain of dependent
// operations, and two independent registers in flight hide its latency. Every path gives the same results
// per lane, except that AVX builds fuse multiply-adds. Value type.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#if defined(__AVX__)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#include <xmmintrin.h>
#endif

namespace strata {

namespace simd {
// One hardware register and its operations; WideFloat strings kRegisters of them together.
#if defined(__AVX__)
using Register = __m256;
inline constexpr int kRegisterLanes = 8;
inline Register Broadcast(float f) {
  return _mm256_set1_ps(f);
}
inline Register Load(const float* aligned) {
  return _mm256_load_ps(aligned);
}
inline void Store(float* aligned, Register r) {
  _mm256_store_ps(aligned, r);
}
inline Register Add(Register a, Register b) {
  return _mm256_add_ps(a, b);
}
inline Register Sub(Register a, Register b) {
  return _mm256_sub_ps(a, b);
}
inline Register Mul(Register a, Register b) {
  return _mm256_mul_ps(a, b);
}
inline Register Div(Register a, Register b) {
  return _mm256_div_ps(a, b);
}
inline Register Min(Register a, Register b) {
  return _mm256_min_ps(a, b);
}
inline Register Max(Register a, Register b) {
  return _mm256_max_ps(a, b);
}
inline Register Sqrt(Register a) {
  return _mm256_sqrt_ps(a);
}
inline Register Greater(Register a, Register b) {
  return _mm256_cmp_ps(a, b, _CMP_GT_OQ);
}
inline Register Select(Register mask, Register if_true, Register if_false) {
  return _mm256_blendv_ps(if_false, if_true, mask);
}
inline Register MulAdd(Register a, Register b, Register c) {
#if defined(__FMA__)
  return _mm256_fmadd_ps(a, b, c);
#else
  return _mm256_add_ps(_mm256_mul_ps(a, b), c);
#endif
}
#elif defined(__SSE2__)
using Register = __m128;
inline constexpr int kRegisterLanes = 4;
inline Register Broadcast(float f) {
  return _mm_set1_ps(f);
}
inline Register Load(const float* aligned) {
  return _mm_load_ps(aligned);
}
inline void Store(float* aligned, Register r) {
  _mm_store_ps(aligned, r);
}
inline Register Add(Register a, Register b) {
  return _mm_add_ps(a, b);
}
inline Register Sub(Register a, Register b) {
  return _mm_sub_ps(a, b);
}
inline Register Mul(Register a, Register b) {
  return _mm_mul_ps(a, b);
}
inline Register Div(Register a, Register b) {
  return _mm_div_ps(a, b);
}
inline Register Min(Register a, Register b) {
  return _mm_min_ps(a, b);
}
inline Register Max(Register a, Register b) {
  return _mm_max_ps(a, b);
}
inline Register Sqrt(Register a) {
  return _mm_sqrt_ps(a);
}
inline Register Greater(Register a, Register b) {
  return _mm_cmpgt_ps(a, b);
}
inline Register Select(Register mask, Register if_true, Register if_false) {
  return _mm_or_ps(_mm_and_ps(mask, if_true), _mm_andnot_ps(mask, if_false));
}
inline Register MulAdd(Register a, Register b, Register c) {
  return _mm_add_ps(_mm_mul_ps(a, b), c);
}
#else
inline constexpr int kRegisterLanes = 4;
struct alignas(16) Register {
  float lane[kRegisterLanes];
};
template <class Op>
Register Apply(Register a, Register b, Op op) {
  Register r;
  for (int i = 0; i < kRegisterLanes; ++i) r.lane[i] = op(a.lane[i], b.lane[i]);
  return r;
}
inline Register Broadcast(float f) {
  return {{f, f, f, f}};
}
inline Register Load(const float* aligned) {
  return {{aligned[0], aligned[1], aligned[2], aligned[3]}};
}
inline void Store(float* aligned, Register r) {
  for (int i = 0; i < kRegisterLanes; ++i) aligned[i] = r.lane[i];
}
inline Register Add(Register a, Register b) {
  return Apply(a, b, [](float x, float y) { return x + y; });
}
inline Register Sub(Register a, Register b) {
  return Apply(a, b, [](float x, float y) { return x - y; });
}
inline Register Mul(Register a, Register b) {
  return Apply(a, b, [](float x, float y) { return x * y; });
}
inline Register Div(Register a, Register b) {
  return Apply(a, b, [](float x, float y) { return x / y; });
}
inline Register Min(Register a, Register b) {
  return Apply(a, b, [](float x, float y) { return y < x ? y : x; });
}
inline Register Max(Register a, Register b) {
  return Apply(a, b, [](float x, float y) { return y > x ? y : x; });
}
inline Register Sqrt(Register a) {
  return Apply(a, a, [](float x, float) { return std::sqrt(x); });
}
inline Register Greater(Register a, Register b) {
  return Apply(a, b, [](float x, float y) { return std::bit_cast<float>(x > y ? 0xffffffffu : 0u); });
}
inline Register Select(Register mask, Register if_true, Register if_false) {
  Register r;
  for (int i = 0; i < kRegisterLanes; ++i)
    r.lane[i] = std::bit_cast<std::uint32_t>(mask.lane[i]) != 0 ? if_true.lane[i] : if_false.lane[i];
  return r;
}
inline Register MulAdd(Register a, Register b, Register c) {
  return Add(Mul(a, b), c);
}
#endif
}  // namespace simd

/// kLanes float lanes in two registers; comparisons give masks (all bits set where true) of the same type.
/// The registers are two named members, not an array, so the compiler keeps them in registers.
struct WideFloat {
  static constexpr int kLanes = 2 * simd::kRegisterLanes;

  simd::Register low, high;

  WideFloat() = default;
  WideFloat(simd::Register l, simd::Register h) : low(l), high(h) {}
  explicit WideFloat(float value) : low(simd::Broadcast(value)), high(simd::Broadcast(value)) {}
  static WideFloat Load(const float* aligned) {
    return {simd::Load(aligned), simd::Load(aligned + simd::kRegisterLanes)};
  }
  void Store(float* aligned) const {
    simd::Store(aligned, low);
    simd::Store(aligned + simd::kRegisterLanes, high);
  }
  static WideFloat Zero() { return WideFloat(0.0f); }
  /// A mask with every lane set.
  static WideFloat AllSet() { return WideFloat(std::bit_cast<float>(0xffffffffu)); }

  friend WideFloat operator+(WideFloat a, WideFloat b) {
    return {simd::Add(a.low, b.low), simd::Add(a.high, b.high)};
  }
  friend WideFloat operator-(WideFloat a, WideFloat b) {
    return {simd::Sub(a.low, b.low), simd::Sub(a.high, b.high)};
  }
  friend WideFloat operator*(WideFloat a, WideFloat b) {
    return {simd::Mul(a.low, b.low), simd::Mul(a.high, b.high)};
  }
  friend WideFloat operator/(WideFloat a, WideFloat b) {
    return {simd::Div(a.low, b.low), simd::Div(a.high, b.high)};
  }
  friend WideFloat Min(WideFloat a, WideFloat b) {
    return {simd::Min(a.low, b.low), simd::Min(a.high, b.high)};
  }
  friend WideFloat Max(WideFloat a, WideFloat b) {
    return {simd::Max(a.low, b.low), simd::Max(a.high, b.high)};
  }
  friend WideFloat Greater(WideFloat a, WideFloat b) {
    return {simd::Greater(a.low, b.low), simd::Greater(a.high, b.high)};
  }
  friend WideFloat Sqrt(WideFloat a) { return {simd::Sqrt(a.low), simd::Sqrt(a.high)}; }
  /// `mask` lanes from `if_true`, the others from `if_false`.
  friend WideFloat Select(WideFloat mask, WideFloat if_true, WideFloat if_false) {
    return {simd::Select(mask.low, if_true.low, if_false.low),
            simd::Select(mask.high, if_true.high, if_false.high)};
  }
  /// a * b + c.
  friend WideFloat MulAdd(WideFloat a, WideFloat b, WideFloat c) {
    return {simd::MulAdd(a.low, b.low, c.low), simd::MulAdd(a.high, b.high, c.high)};
  }
  WideFloat& operator+=(WideFloat other) { return *this = *this + other; }
  WideFloat& operator-=(WideFloat other) { return *this = *this - other; }
};

/// Three WideFloat: one 3-vector per lane.
struct WideVec3 {
  WideFloat x, y, z;

  static WideVec3 Zero() { return {WideFloat::Zero(), WideFloat::Zero(), WideFloat::Zero()}; }
  friend WideVec3 operator+(const WideVec3& a, const WideVec3& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
  }
  friend WideVec3 operator-(const WideVec3& a, const WideVec3& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
  }
  friend WideVec3 operator*(WideFloat s, const WideVec3& a) { return {s * a.x, s * a.y, s * a.z}; }
  WideVec3& operator+=(const WideVec3& other) { return *this = *this + other; }
  WideVec3& operator-=(const WideVec3& other) { return *this = *this - other; }
};

namespace simd {
// Four rows of four floats <-> four registers of one component each, for the lanes [first, first + 4).
#if defined(__AVX__) || defined(__SSE2__)
inline void Transpose4(const float* const* rows, __m128& x, __m128& y, __m128& z, __m128& w) {
  x = _mm_load_ps(rows[0]), y = _mm_load_ps(rows[1]), z = _mm_load_ps(rows[2]), w = _mm_load_ps(rows[3]);
  _MM_TRANSPOSE4_PS(x, y, z, w);
}
inline void Untranspose4(float* const* rows, __m128 x, __m128 y, __m128 z, __m128 w) {
  _MM_TRANSPOSE4_PS(x, y, z, w);
  if (rows[0] != nullptr) _mm_store_ps(rows[0], x);
  if (rows[1] != nullptr) _mm_store_ps(rows[1], y);
  if (rows[2] != nullptr) _mm_store_ps(rows[2], z);
  if (rows[3] != nullptr) _mm_store_ps(rows[3], w);
}
#endif
#if defined(__AVX__)
inline void Gather(const float* const* rows, Register& x, Register& y, Register& z, Register& w) {
  __m128 x0, y0, z0, w0, x1, y1, z1, w1;
  Transpose4(rows, x0, y0, z0, w0);
  Transpose4(rows + 4, x1, y1, z1, w1);
  x = _mm256_set_m128(x1, x0), y = _mm256_set_m128(y1, y0), z = _mm256_set_m128(z1, z0);
  w = _mm256_set_m128(w1, w0);
}
inline void Scatter(float* const* rows, Register x, Register y, Register z, Register w) {
  Untranspose4(rows, _mm256_castps256_ps128(x), _mm256_castps256_ps128(y), _mm256_castps256_ps128(z),
               _mm256_castps256_ps128(w));
  Untranspose4(rows + 4, _mm256_extractf128_ps(x, 1), _mm256_extractf128_ps(y, 1),
               _mm256_extractf128_ps(z, 1), _mm256_extractf128_ps(w, 1));
}
#elif defined(__SSE2__)
inline void Gather(const float* const* rows, Register& x, Register& y, Register& z, Register& w) {
  Transpose4(rows, x, y, z, w);
}
inline void Scatter(float* const* rows, Register x, Register y, Register z, Register w) {
  Untranspose4(rows, x, y, z, w);
}
#else
inline void Gather(const float* const* rows, Register& x, Register& y, Register& z, Register& w) {
  for (int i = 0; i < kRegisterLanes; ++i)
    x.lane[i] = rows[i][0], y.lane[i] = rows[i][1], z.lane[i] = rows[i][2], w.lane[i] = rows[i][3];
}
inline void Scatter(float* const* rows, Register x, Register y, Register z, Register w) {
  for (int i = 0; i < kRegisterLanes; ++i) {
    if (rows[i] == nullptr) continue;
    rows[i][0] = x.lane[i], rows[i][1] = y.lane[i], rows[i][2] = z.lane[i], rows[i][3] = w.lane[i];
  }
}
#endif
}  // namespace simd

/// Lane i gets the four floats at rows[i] (16-byte aligned) as x, y, z, w: a transpose in registers.
inline void GatherRows(const float* const* rows, WideFloat& x, WideFloat& y, WideFloat& z, WideFloat& w) {
  simd::Gather(rows, x.low, y.low, z.low, w.low);
  simd::Gather(rows + simd::kRegisterLanes, x.high, y.high, z.high, w.high);
}
/// The reverse of GatherRows; lanes whose row pointer is null are not written.
inline void ScatterRows(float* const* rows, const WideFloat& x, const WideFloat& y, const WideFloat& z,
                        const WideFloat& w) {
  simd::Scatter(rows, x.low, y.low, z.low, w.low);
  simd::Scatter(rows + simd::kRegisterLanes, x.high, y.high, z.high, w.high);
}

inline WideFloat Dot(const WideVec3& a, const WideVec3& b) {
  return MulAdd(a.x, b.x, MulAdd(a.y, b.y, a.z * b.z));
}
inline WideVec3 Cross(const WideVec3& a, const WideVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// s * a + b, per component.
inline WideVec3 MulAdd(WideFloat s, const WideVec3& a, const WideVec3& b) {
  return {MulAdd(s, a.x, b.x), MulAdd(s, a.y, b.y), MulAdd(s, a.z, b.z)};
}

}  // namespace strata
