// Lanes of cells: the number type a cell model is written over.
//
// A model's equations are written once, as a generic function of its number
// type R, and run two ways:
//   R = fibrodem::simd::Real  a SIMD register of kLanes cells (xsimd batch of
//                             double, the widest the compiler targets: 8 with
//                             AVX-512, 4 with AVX2, 2 with SSE2 or NEON);
//   R = double                one cell at a time (the scalar reference path,
//                             solver.simd false).
// Everything the equations need works for both: arithmetic with double
// constants, comparisons, and the functions below. A model calls them
// unqualified after FIBRODEM_USE_LANE_MATH in its (unnamed) namespace: those
// using-declarations hide ::exp and friends, so exp(x) is the same function
// family for double and for lanes.
//
// The vector exp/log/expm1/pow are xsimd's (header-only, from Debian's
// libxsimd-dev; max error ~1 ulp). SLEEF (u10) and glibc's libmvec were
// measured on colman too; docs/topics/performance.md#how says why xsimd.
#pragma once

#include <cmath>
#include <cstddef>

// GCC 12 without optimisation (-O0, as in Debug builds) defines
// _mm512_mask_blend_epi8/_epi16 as macros that C-cast their operands to byte
// and word vectors, which an xsimd batch object cannot take; xsimd 8's AVX512BW
// select (Debian 12's libxsimd-dev) hands them batch objects in a branch it
// also compiles for 32- and 64-bit lanes (a runtime switch on sizeof(T)), so
// every translation unit that reaches select on int64 lanes (xsimd::log does)
// fails to compile at -O0 with -march=x86-64-v4 or an AVX-512 -march=native
// ("invalid cast ... to type '__v64qi'"). xsimd 10 passes the registers
// instead (xsimd pull request 852). The two macros are redefined here to take
// the register first, as GCC's own inline functions do when optimising; with
// optimisation on (or another compiler or ISA) nothing here applies, so
// optimised code is unchanged. xsimd must be included through this header for
// the redefinition to precede its templates.
#if defined(__GNUC__) && !defined(__clang__) && !defined(__OPTIMIZE__) && defined(__AVX512BW__)
#include <immintrin.h>
#undef _mm512_mask_blend_epi8
#undef _mm512_mask_blend_epi16
#define _mm512_mask_blend_epi8(mask, a, b)                                               \
  ((__m512i)__builtin_ia32_blendmb_512_mask((__v64qi)(__m512i)(a), (__v64qi)(__m512i)(b), \
                                            (__mmask64)(mask)))
#define _mm512_mask_blend_epi16(mask, a, b)                                              \
  ((__m512i)__builtin_ia32_blendmw_512_mask((__v32hi)(__m512i)(a), (__v32hi)(__m512i)(b), \
                                            (__mmask32)(mask)))
#endif
#include <xsimd/xsimd.hpp>

// Small lane functions are always inlined: a call per function and lane group
// costs more than the work in it (GCC otherwise declines in large models).
#define FIBRODEM_LANE_INLINE inline __attribute__((always_inline))

namespace fibrodem::simd {

using Real = xsimd::batch<double>;
inline constexpr std::size_t kLanes = Real::size;

// ---- comparisons give bool for double, a lane mask for Real ----------------
// select(mask, a, b): a where the mask holds, else b (both are evaluated; the
// unused one may be inf or NaN).
FIBRODEM_LANE_INLINE double select(bool mask, double a, double b) { return mask ? a : b; }
FIBRODEM_LANE_INLINE Real select(const Real::batch_bool_type& mask, const Real& a, const Real& b) {
  return xsimd::select(mask, a, b);
}
FIBRODEM_LANE_INLINE Real select(const Real::batch_bool_type& mask, double a, const Real& b) {
  return xsimd::select(mask, Real(a), b);
}
FIBRODEM_LANE_INLINE Real select(const Real::batch_bool_type& mask, const Real& a, double b) {
  return xsimd::select(mask, a, Real(b));
}
FIBRODEM_LANE_INLINE Real select(const Real::batch_bool_type& mask, double a, double b) {
  return xsimd::select(mask, Real(a), Real(b));
}

// ---- loads and stores of n <= kLanes consecutive values ---------------------
// A group narrower than the register repeats its last value in the spare lanes
// (so they hold valid numbers) and stores only its own values: every cell then
// goes through the same vector code wherever it sits in its block.
FIBRODEM_LANE_INLINE Real load(const double* p, std::size_t n) {
  if (n == kLanes) return Real::load_unaligned(p);
  if (n == 1) return Real(*p);  // a single cell: one broadcast
  alignas(64) double lanes[kLanes];
  for (std::size_t i = 0; i < kLanes; ++i) lanes[i] = p[i < n ? i : n - 1];
  return Real::load_aligned(lanes);
}
FIBRODEM_LANE_INLINE void store(double* p, const Real& value, std::size_t n) {
  if (n == kLanes) return value.store_unaligned(p);
  alignas(64) double lanes[kLanes];
  value.store_aligned(lanes);
  for (std::size_t i = 0; i < n; ++i) p[i] = lanes[i];
}

// ---- elementary functions ---------------------------------------------------
FIBRODEM_LANE_INLINE double exp(double x) { return std::exp(x); }
FIBRODEM_LANE_INLINE Real exp(const Real& x) { return xsimd::exp(x); }
FIBRODEM_LANE_INLINE double expm1(double x) { return std::expm1(x); }
FIBRODEM_LANE_INLINE Real expm1(const Real& x) { return xsimd::expm1(x); }
FIBRODEM_LANE_INLINE double log(double x) { return std::log(x); }
FIBRODEM_LANE_INLINE Real log(const Real& x) { return xsimd::log(x); }
FIBRODEM_LANE_INLINE double sqrt(double x) { return std::sqrt(x); }
FIBRODEM_LANE_INLINE Real sqrt(const Real& x) { return xsimd::sqrt(x); }
FIBRODEM_LANE_INLINE double fabs(double x) { return std::fabs(x); }
FIBRODEM_LANE_INLINE Real fabs(const Real& x) { return xsimd::abs(x); }
FIBRODEM_LANE_INLINE double pow(double x, double y) { return std::pow(x, y); }
FIBRODEM_LANE_INLINE Real pow(const Real& x, double y) { return xsimd::pow(x, Real(y)); }
FIBRODEM_LANE_INLINE Real pow(const Real& x, const Real& y) { return xsimd::pow(x, y); }
FIBRODEM_LANE_INLINE Real pow(double x, const Real& y) { return xsimd::pow(Real(x), y); }
FIBRODEM_LANE_INLINE double fmin(double a, double b) { return std::fmin(a, b); }
FIBRODEM_LANE_INLINE Real fmin(const Real& a, const Real& b) { return xsimd::min(a, b); }
FIBRODEM_LANE_INLINE double fmax(double a, double b) { return std::fmax(a, b); }
FIBRODEM_LANE_INLINE Real fmax(const Real& a, const Real& b) { return xsimd::max(a, b); }
FIBRODEM_LANE_INLINE double floor(double x) { return std::floor(x); }
FIBRODEM_LANE_INLINE Real floor(const Real& x) { return xsimd::floor(x); }

// x / (1 - exp(-x)), with its limit 1 + x/2 near x = 0: the removable
// singularity of Hodgkin-Huxley rates such as a (V - V0) / (1 - exp(-(V - V0)/k)).
// expm1 keeps full relative accuracy for small |x|.
template <class R>
FIBRODEM_LANE_INLINE R exprel(const R& x) {
  return select(fabs(x) < 1e-6, 1.0 + 0.5 * x, x / -expm1(-x));
}

}  // namespace fibrodem::simd

// The elementary functions above, for unqualified use in a model's namespace.
#define FIBRODEM_USE_LANE_MATH       \
  using fibrodem::simd::select;      \
  using fibrodem::simd::exp;         \
  using fibrodem::simd::expm1;       \
  using fibrodem::simd::log;         \
  using fibrodem::simd::sqrt;        \
  using fibrodem::simd::fabs;        \
  using fibrodem::simd::pow;         \
  using fibrodem::simd::fmin;        \
  using fibrodem::simd::fmax;        \
  using fibrodem::simd::floor;       \
  using fibrodem::simd::exprel
