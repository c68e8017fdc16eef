#include "coupling/coupling_cg.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "model/work_split.hpp"

namespace fibrodem {

namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
// Rounding's drift of the recurrence's residual from the true one, in units
// of eps |dt C^-1 A|_inf max|v| per iteration (Greenbaum's constant is a few
// units: twice that).
constexpr double kDriftPerIteration = 8;

}  // namespace

// The off-diagonal entries in slices of kSlice rows, entry k of a slice's
// rows side by side, each row's entries in L's order; a row's diagonal
// place is before its first entry past the diagonal in the tissue's column
// order (row_current).
template <class Entries>
void CouplingCg::slice_rows(Entries&& entries, long ghosts) {
  const long slices = padded_ / kSlice;
  start_.assign(static_cast<std::size_t>(slices) + 1, 0);
  width_.assign(static_cast<std::size_t>(slices), 0);
  for (long s = 0; s < slices; ++s) {
    for (long lane = 0; lane < kSlice && s * kSlice + lane < n_; ++lane) {
      int count = 0;
      entries(s * kSlice + lane, [&](int, double, bool) { ++count; });
      width_[s] = std::max(width_[s], count);
    }
    start_[s + 1] = start_[s] + width_[s] * kSlice;
  }
  column_.resize(static_cast<std::size_t>(start_[slices]));
  weight_nS_.assign(static_cast<std::size_t>(start_[slices]), 0.0);
  row_length_.assign(static_cast<std::size_t>(padded_), 0);
  diagonal_position_.assign(static_cast<std::size_t>(padded_), 0);
  for (long s = 0; s < slices; ++s)
    for (long lane = 0; lane < kSlice; ++lane) {
      const long i = s * kSlice + lane;
      long k = 0, diagonal_at = -1;
      if (i < n_)
        entries(i, [&](int j, double weight, bool past_diagonal) {
          if (diagonal_at < 0 && past_diagonal) diagonal_at = k;
          column_[start_[s] + k * kSlice + lane] = j;
          weight_nS_[start_[s] + k * kSlice + lane] = weight;
          ++k;
        });
      row_length_[static_cast<std::size_t>(i)] = static_cast<int>(k);
      diagonal_position_[static_cast<std::size_t>(i)] = static_cast<int>(diagonal_at < 0 ? k : diagonal_at);
      for (; k < width_[s]; ++k) column_[start_[s] + k * kSlice + lane] = static_cast<int>(i);  // weight 0
    }
  for (auto* v : {&x_, &r_, &z_, &p_, &q_})
    v->assign(static_cast<std::size_t>(padded_ + ghosts), 0.0);
  const std::size_t chunks = static_cast<std::size_t>((padded_ + kRowsPerChunk - 1) / kRowsPerChunk);
  chunk_dot_.assign(chunks, 0.0);
  chunk_largest_.assign(chunks, 0.0);
}

// Row k's 1/C and L_ii, from the tissue's cell cell_of(k), and the largest
// L_ii / C_i of the rows. Rows past n_ (padding) hold zeros throughout (r,
// z, p, q, x): their entries and L_ii are 0, so they add nothing to any sum.
// Their 1/C is 1, so that A's diagonal is C/dt > 0 there too and its
// inverse needs no guard (kPaddingInverseCapacitance).
template <class CellOf>
void CouplingCg::take_diagonal(const Laplacian& laplacian, const std::vector<double>& capacitance_pF, CellOf&& cell_of) {
  padded_ = (n_ + kSlice - 1) / kSlice * kSlice;
  diagonal_nS_.assign(static_cast<std::size_t>(padded_), 0.0);
  inverse_capacitance_.assign(static_cast<std::size_t>(padded_), kPaddingInverseCapacitance);
  const int* outer = laplacian.outerIndexPtr();
  const int* column = laplacian.innerIndexPtr();
  const double* value = laplacian.valuePtr();
  for (long k = 0; k < n_; ++k) {
    const int i = cell_of(k);
    if (!(capacitance_pF[i] > 0))
      throw std::invalid_argument(fmt::format("coupling CG: cell {} has capacitance {} pF, expected > 0", i,
                                              capacitance_pF[i]));
    inverse_capacitance_[k] = 1.0 / capacitance_pF[i];
    for (int e = outer[i]; e < outer[i + 1]; ++e)
      if (column[e] == i) diagonal_nS_[k] = value[e];
    max_rate_per_ms_ = std::max(max_rate_per_ms_, diagonal_nS_[k] * inverse_capacitance_[k]);
  }
}

CouplingCg::CouplingCg(const Laplacian& laplacian, std::vector<double> capacitance_pF, int max_iterations)
    : n_(laplacian.rows()), max_iterations_(max_iterations) {
  if (static_cast<long>(capacitance_pF.size()) != n_)
    throw std::invalid_argument(fmt::format("coupling CG: {} capacitances for {} cells", capacitance_pF.size(), n_));
  take_diagonal(laplacian, capacitance_pF, [](long i) { return static_cast<int>(i); });
  const int* outer = laplacian.outerIndexPtr();
  const int* column = laplacian.innerIndexPtr();
  const double* value = laplacian.valuePtr();
  slice_rows(
      [&](long i, auto&& emit) {
        for (int e = outer[i]; e < outer[i + 1]; ++e)
          if (column[e] != i) emit(column[e], value[e], column[e] > i);
      },
      0);
}

CouplingCg::CouplingCg(const Laplacian& laplacian, const std::vector<double>& capacitance_pF,
                       const CellNumbering& held, Ranks& ranks)
    : n_(static_cast<long>(held.own())), max_iterations_(kMaxIterations), ranks_(&ranks) {
  take_diagonal(laplacian, capacitance_pF, [](long k) { return static_cast<int>(k); });
  const int* outer = laplacian.outerIndexPtr();
  const int* column = laplacian.innerIndexPtr();
  const double* value = laplacian.valuePtr();
  slice_rows(
      [&](long k, auto&& emit) {
        const int cell = held.tissue_cell(static_cast<std::size_t>(k));
        for (int e = outer[k]; e < outer[k + 1]; ++e) {
          const int j = column[e];
          if (j == k) continue;
          // A ghost's column here comes past the padded rows; the entry is
          // past the diagonal by tissue cell (the row is in the tissue's
          // column order, whatever its columns' numbers here).
          const long here = j < n_ ? j : padded_ + (j - n_);
          emit(static_cast<int>(here), value[e], held.tissue_cell(static_cast<std::size_t>(j)) > cell);
        }
      },
      static_cast<long>(held.held() - held.own()));
  // The whole tissue's largest rate: every rank's drift allowance alike.
  double unused = 0;
  ranks.reduce(unused, max_rate_per_ms_);
}

// f(first_row, end_row) -> Sums for each chunk of kRowsPerChunk rows (whole
// slices), on the OpenMP threads from kParallelCells rows on (below, a
// parallel region costs more than the pass); the chunks' sums added in chunk
// order, so that they do not depend on the threads.
template <class F>
CouplingCg::Sums CouplingCg::over_chunks(F&& f) {
  const long chunks = static_cast<long>(chunk_dot_.size());
  const auto run = [&](long c) {
    const Sums s = f(c * kRowsPerChunk, std::min(padded_, (c + 1) * kRowsPerChunk));
    chunk_dot_[c] = s.dot;
    chunk_largest_[c] = s.largest;
  };
  if (n_ <= kParallelCells) {
    for (long c = 0; c < chunks; ++c) run(c);
  } else {
#pragma omp parallel for schedule(static)
    for (long c = 0; c < chunks; ++c) run(c);
  }
  Sums total;
  for (long c = 0; c < chunks; ++c) {
    total.dot += chunk_dot_[c];
    total.largest = std::max(total.largest, chunk_largest_[c]);
  }
  if (ranks_) ranks_->reduce(total.dot, total.largest);
  return total;
}

inline void CouplingCg::slice_product(long s, const double* y, double* sum) const {
  std::fill(sum, sum + kSlice, 0.0);
  for (long k = 0; k < width_[s]; ++k) {
    const int* column = column_.data() + start_[s] + k * kSlice;
    const double* weight = weight_nS_.data() + start_[s] + k * kSlice;
    for (long lane = 0; lane < kSlice; ++lane) sum[lane] += weight[lane] * y[column[lane]];
  }
}

template <class Potential>
double CouplingCg::current_of_row(long i, Potential&& V) const {
  // The row's entries in L's column order, the diagonal in its place: the
  // sum L's compressed rows gave, term by term in the same order and by a
  // loop of the same shape (whether its chain of products is fused into
  // FMAs), so the currents keep their bits.
  // (Indices, not pointers: a tissue without junctions has no entries at all.)
  const long s = i / kSlice, first = start_[s] + i % kSlice;
  const long before = diagonal_position_[static_cast<std::size_t>(i)], length = row_length_[static_cast<std::size_t>(i)];
  double current = 0.0;
  long k = 0;
  for (; k < before; ++k) current -= weight_nS_[first + k * kSlice] * V(column_[first + k * kSlice]);
  // (No diagonal entry: a cell without junctions.)
  if (const double diagonal = diagonal_nS_[static_cast<std::size_t>(i)]; diagonal != 0) current -= diagonal * V(i);
  for (; k < length; ++k) current -= weight_nS_[first + k * kSlice] * V(column_[first + k * kSlice]);
  return current;
}

double CouplingCg::row_current(long i, const double* V) const {
  return current_of_row(i, [V](long j) { return V[j]; });
}

double CouplingCg::row_current(long i, const double* V, const int* cell_of_column) const {
  return current_of_row(i, [V, cell_of_column](long j) { return V[cell_of_column[j]]; });
}

std::vector<double> CouplingCg::diagonal_nS() const {
  return {diagonal_nS_.begin(), diagonal_nS_.begin() + n_};
}

CouplingCg::Sums CouplingCg::residual(const double* v, double* x, double dt_ms) {
  inverse_dt_ = 1.0 / dt_ms;
  refresh_ghosts(x);
  return over_chunks([&](long first, long end) {
    Sums s;
    for (long slice = first / kSlice; slice < end / kSlice; ++slice) {
      double sum[kSlice];
      slice_product(slice, x, sum);
      for (long lane = 0; lane < kSlice; ++lane) {
        const long i = slice * kSlice + lane;
        const double C_over_dt = inverse_dt_ / inverse_capacitance_[i];
        const double v_i = i < n_ ? v[i] : 0.0;  // (padding: 0)
        const double r = C_over_dt * (v_i - x[i]) - (sum[lane] + diagonal_nS_[i] * x[i]);
        r_[i] = r;
        z_[i] = inverse_diagonal(i) * r;
        p_[i] = q_[i] = 0;
        s.dot += r * z_[i];
        s.largest = std::max(s.largest, std::abs(r) * inverse_capacitance_[i]);
      }
    }
    return s;
  });
}

double CouplingCg::direction(double beta) {
  refresh_ghosts(z_.data());
  return over_chunks([&](long first, long end) {
           Sums s;
           for (long slice = first / kSlice; slice < end / kSlice; ++slice) {
             double sum[kSlice];
             slice_product(slice, z_.data(), sum);
             for (long lane = 0; lane < kSlice; ++lane) {
               const long i = slice * kSlice + lane;
               const double Az = a_diagonal(i) * z_[i] + sum[lane];
               p_[i] = z_[i] + beta * p_[i];
               q_[i] = Az + beta * q_[i];
               s.dot += p_[i] * q_[i];
             }
           }
           return s;
         })
      .dot;
}

int CouplingCg::solve(double* x_io, double dt_ms, double tolerance_mV) {
  // The start: v plus the last solve's correction x - v, scaled to this dt.
  const double scale = last_dt_ms_ > 0 ? dt_ms / last_dt_ms_ : 0.0;
  double v_max = 0;
  // (v stays in x_io, untouched until the solve is done.)
  const double* v = x_io;
  for (long i = 0; i < n_; ++i) {
    x_[i] = scale > 0 ? v[i] + scale * x_[i] : v[i];  // (x_ holds the correction between solves)
    v_max = std::max(v_max, std::abs(v[i]));
  }
  if (ranks_) {  // every rank's largest, for the same drift allowance and the same test of v
    double unused = 0;
    ranks_->reduce(unused, v_max);
  }
  double* x = x_.data();
  const double drift_per_iteration = kDriftPerIteration * kEpsilon * (1 + 2 * dt_ms * max_rate_per_ms_) * v_max;
  Sums s = residual(v, x, dt_ms);
  double rz = s.dot, bound = dt_ms * s.largest;
  int iterations = 0, since_restart = 0;
  while (std::isfinite(rz) && std::isfinite(v_max)) {  // else a NaN or infinite v: the caller's to see
    double beta = 0;
    while (bound + since_restart * drift_per_iteration > tolerance_mV) {
      if (iterations >= max_iterations_) fail(dt_ms, tolerance_mV, bound, iterations);
      ++iterations;
      ++since_restart;
      const double alpha = rz / direction(beta);
      s = over_chunks([&](long first, long end) {
        Sums chunk;
        for (long i = first; i < end; ++i) {
          x[i] += alpha * p_[i];
          r_[i] -= alpha * q_[i];
          z_[i] = inverse_diagonal(i) * r_[i];
          chunk.dot += r_[i] * z_[i];
          chunk.largest = std::max(chunk.largest, std::abs(r_[i]) * inverse_capacitance_[i]);
        }
        return chunk;
      });
      bound = dt_ms * s.largest;
      if (!std::isfinite(s.dot)) fail(dt_ms, tolerance_mV, bound, iterations);
      if (s.dot == 0) break;  // (an exact zero residual: no direction left; the check below decides)
      beta = s.dot / rz;
      rz = s.dot;
    }
    // Where rounding may have moved the recurrence's residual by a tenth of
    // the tolerance, the bound from the true residual; CG restarts from it if
    // that is still above the tolerance.
    if (since_restart * drift_per_iteration <= 0.1 * tolerance_mV) break;
    s = residual(v, x, dt_ms);
    rz = s.dot;
    bound = dt_ms * s.largest;
    since_restart = 0;
    if (bound <= tolerance_mV) break;
  }
  if (std::isfinite(rz)) {
    for (long i = 0; i < n_; ++i) {
      const double x_i = x_[i];
      x_[i] = x_i - v[i];  // the correction, for the next solve's start (v is x_io: read before it is written)
      x_io[i] = x_i;
    }
    last_dt_ms_ = dt_ms;
  } else {
    last_dt_ms_ = 0;  // x_ holds no correction: the next solve starts from v alone
  }
  ++statistics_.solves;
  statistics_.iterations += iterations;
  statistics_.most_iterations = std::max(statistics_.most_iterations, iterations);
  return iterations;
}

void CouplingCg::fail(double dt_ms, double tolerance_mV, double bound_mV, int iterations) const {
  throw std::runtime_error(fmt::format(
      "gap-junction coupling: conjugate gradients did not reach the tolerance of {:.3g} mV on the potential in {} "
      "iterations (dt {:.6g} ms, {} cells; the error bound is still {:.3g} mV): the tolerance is below what "
      "rounding allows (solver.atol too small?), or C/dt + L is too badly conditioned for the Jacobi "
      "preconditioner",
      tolerance_mV, iterations, dt_ms, n_, bound_mV));
}

std::string CouplingCg::describe_statistics() const {
  if (statistics_.solves == 0) return "no coupling solves";
  return fmt::format("{} coupling solves, {:.2f} CG iterations each (at most {})", statistics_.solves,
                     static_cast<double>(statistics_.iterations) / static_cast<double>(statistics_.solves),
                     statistics_.most_iterations);
}

}  // namespace fibrodem
