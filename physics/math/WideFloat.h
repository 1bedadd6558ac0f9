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

/// kLanes float lanes; comparisons give masks (all bits set where true) of the same type.
struct WideFloat {
  static constexpr int kRegisters = 2;
  static constexpr int kLanes = kRegisters * simd::kRegisterLanes;

  simd::Register r[kRegisters];

  WideFloat() = default;
  explicit WideFloat(float value) {
    for (simd::Register& reg : r) reg = simd::Broadcast(value);
  }
  static WideFloat Load(const float* aligned) {
    WideFloat w;
    for (int i = 0; i < kRegisters; ++i) w.r[i] = simd::Load(aligned + i * simd::kRegisterLanes);
    return w;
  }
  void Store(float* aligned) const {
    for (int i = 0; i < kRegisters; ++i) simd::Store(aligned + i * simd::kRegisterLanes, r[i]);
  }
  static WideFloat Zero() { return WideFloat(0.0f); }
  /// A mask with every lane set.
  static WideFloat AllSet() { return WideFloat(std::bit_cast<float>(0xffffffffu)); }

  template <class Op>
  static WideFloat Map(WideFloat a, WideFloat b, Op op) {
    WideFloat w;
    for (int i = 0; i < kRegisters; ++i) w.r[i] = op(a.r[i], b.r[i]);
    return w;
  }
  friend WideFloat operator+(WideFloat a, WideFloat b) { return Map(a, b, simd::Add); }
  friend WideFloat operator-(WideFloat a, WideFloat b) { return Map(a, b, simd::Sub); }
  friend WideFloat operator*(WideFloat a, WideFloat b) { return Map(a, b, simd::Mul); }
  friend WideFloat operator/(WideFloat a, WideFloat b) { return Map(a, b, simd::Div); }
  friend WideFloat Min(WideFloat a, WideFloat b) { return Map(a, b, simd::Min); }
  friend WideFloat Max(WideFloat a, WideFloat b) { return Map(a, b, simd::Max); }
  friend WideFloat Greater(WideFloat a, WideFloat b) { return Map(a, b, simd::Greater); }
  friend WideFloat Sqrt(WideFloat a) {
    return Map(a, a, [](simd::Register x, simd::Register) { return simd::Sqrt(x); });
  }
  /// `mask` lanes from `if_true`, the others from `if_false`.
  friend WideFloat Select(WideFloat mask, WideFloat if_true, WideFloat if_false) {
    WideFloat w;
    for (int i = 0; i < kRegisters; ++i) w.r[i] = simd::Select(mask.r[i], if_true.r[i], if_false.r[i]);
    return w;
  }
  /// a * b + c.
  friend WideFloat MulAdd(WideFloat a, WideFloat b, WideFloat c) {
    WideFloat w;
    for (int i = 0; i < kRegisters; ++i) w.r[i] = simd::MulAdd(a.r[i], b.r[i], c.r[i]);
    return w;
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
