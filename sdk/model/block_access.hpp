// How a model's equations reach its block of cells (see cell_model.hpp).
//
// A model writes its equations once, as a generic function of a Cells<R>
// accessor, and hands them to for_each_lane_group:
//
//     void evaluate(const BlockView& block, double t) const override {
//       fibrodem::for_each_lane_group(block, [&](const auto& cell) {
//         using R = typename std::decay_t<decltype(cell)>::Real;
//         const R V = cell.state(k_V);
//         ...
//         cell.gate_inf_tau(k_m, m_inf, tau_m);
//       });
//     }
//
// The equations then run on kLanes cells at a time in SIMD registers
// (R = simd::Real), or, when the block asks for the scalar reference path,
// one cell at a time in double (R = double). Both read like the paper.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include "model/cell_model.hpp"
#include "model/simd.hpp"

namespace fibrodem {

// The cells [first, first + count) of a block, as lanes of R (count <= lanes;
// a last, narrower group is padded as simd::load describes).
template <class R>
class Cells {
 public:
  using Real = R;

  Cells(const BlockView& block, std::size_t first, std::size_t count)
      : v_(block), ab_stride_(block.ab_stride ? block.ab_stride : block.stride), c_(first), n_(count) {}

  FIBRODEM_LANE_INLINE R state(int k) const { return load(v_.y + k * v_.stride); }
  FIBRODEM_LANE_INLINE R input(int k) const { return load(v_.inputs + k * v_.stride); }
  FIBRODEM_LANE_INLINE double param(int k) const { return v_.params[k]; }

  // A state that is not a gate: dy/dt given directly.
  FIBRODEM_LANE_INLINE void rate(int k, const R& dydt) const {
    store(v_.a + k * ab_stride_, dydt);
    store(v_.b + k * ab_stride_, R(0.0));
  }
  // A gate from its steady state and time constant: dy/dt = (y_inf - y)/tau.
  FIBRODEM_LANE_INLINE void gate_inf_tau(int k, const R& y_inf, const R& tau) const {
    const R rate = 1.0 / tau;
    store(v_.a + k * ab_stride_, y_inf * rate);
    store(v_.b + k * ab_stride_, -rate);
  }
  // A gate from its opening and closing rates: dy/dt = alpha (1 - y) - beta y.
  FIBRODEM_LANE_INLINE void gate_alpha_beta(int k, const R& alpha, const R& beta) const {
    store(v_.a + k * ab_stride_, alpha);
    store(v_.b + k * ab_stride_, -(alpha + beta));
  }
  // A stiff state that is not a gate: dy/dt with its slope d(dy/dt)/dy (or an
  // approximation of it), written as the linear form a + b y with b = slope.
  // The rate is unchanged; an exponential integrator (solver.method
  // "adaptive") then takes the state stably at steps far beyond 1/|slope|.
  FIBRODEM_LANE_INLINE void stiff_rate(int k, const R& dydt, const R& slope) const {
    linear(k, dydt - slope * state(k), slope);
  }
  // Any other linear form, dy/dt = a + b y (b of the model's own).
  FIBRODEM_LANE_INLINE void linear(int k, const R& a, const R& b) const {
    store(v_.a + k * ab_stride_, a);
    store(v_.b + k * ab_stride_, b);
  }
  FIBRODEM_LANE_INLINE void output(int k, const R& value) const {
    if (v_.outputs != nullptr) store(v_.outputs + k * v_.stride, value);
  }

 private:
  FIBRODEM_LANE_INLINE R load(const double* row) const {
    if constexpr (std::is_same_v<R, double>) return row[c_];
    else return simd::load(row + c_, n_);
  }
  FIBRODEM_LANE_INLINE void store(double* row, const R& value) const {
    if constexpr (std::is_same_v<R, double>) row[c_] = value;
    else simd::store(row + c_, value, n_);
  }

  const BlockView& v_;
  std::size_t ab_stride_, c_, n_;
};

// One cell at a time, for a model that loops over its block itself (the
// scalar style of plugin ABI 2; it gets no SIMD speed-up).
class CellAccess : public Cells<double> {
 public:
  CellAccess(const BlockView& block, std::size_t cell) : Cells<double>(block, cell, 1) {}
};

// Runs equations(cells) over the block: lanes of simd::kLanes cells, or one
// cell at a time in double when block.scalar_reference is set.
// Flattened: the equations and every lane function they call are inlined into
// this loop. Left as calls (GCC declines to inline a model's large body), each
// SIMD store of a rate, whose vector type may alias anything, made the
// compiler reload the accessor's pointers and the parameters after it
// (colman: 12 % fewer instructions per cell-step flattened).
template <class Equations>
__attribute__((flatten)) void for_each_lane_group(const BlockView& block, Equations&& equations) {
  if (block.scalar_reference) {
    for (std::size_t c = block.begin; c < block.end; ++c) equations(Cells<double>(block, c, 1));
    return;
  }
  for (std::size_t c = block.begin; c < block.end; c += simd::kLanes)
    equations(Cells<simd::Real>(block, c, std::min(simd::kLanes, block.end - c)));
}

}  // namespace fibrodem
