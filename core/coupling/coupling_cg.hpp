// Preconditioned conjugate gradients for the implicit gap-junction step
//   (C/dt + L) x = (C/dt) v,
// C the cells' capacitances [pF] (diagonal), L the junctions' graph Laplacian
// [nS] (symmetric, non-positive off the diagonal, rows summing to zero): the
// matrix A is symmetric positive definite, so CG applies.
//
// Start: x = v + (dt / dt_last) (x_last - v_last), v plus the last solve's
// correction scaled to this step (the coupling's pull on a wavefront changes
// little from one step to the next: 2.5 iterations a solve against 6 from v
// alone on the Fig. 3 scene). After restart(), x = v.
//
// Stopping: with r = (C/dt) v - A x the residual, the error is
//   x - x* = -(I + K)^-1 (dt C^-1 r),  K = dt C^-1 L.
// I + K has non-positive entries off the diagonal and rows summing to one, so
// it is an M-matrix whose inverse is non-negative with rows summing to one:
// its max norm is 1, and
//   |x - x*|_inf <= dt max_i |r_i| / C_i.
// CG stops once this bound on its recurrence's residual, plus what rounding
// can have moved that residual from the true b - A x (`drift`, after
// Greenbaum 1997, SIAM J. Matrix Anal. Appl. 18:535, Theorem 2: a few eps
// |A| |x| per iteration), is below the caller's tolerance [mV]. Where the drift
// could matter (above a tenth of the tolerance) the bound is taken again from
// the true residual before returning.
//
// Preconditioner: Jacobi (D, the diagonal C/dt + L_ii). The eigenvalues of
// D^-1 A lie between 1 / (1 + dt max_i(L_ii / C_i)) (as A >= C/dt) and 2
// (Gershgorin) whatever the tissue's size (C/dt dominates the smooth modes
// that make a Laplacian hard), and the start is close: the Fig. 3 scenes
// take 2-3 iterations a solve at 3k to 200k cells. Incomplete Cholesky
// (Eigen's IncompleteCholesky, AMD order) halves the iterations, but its two
// triangular solves cost more than the products they save and run on one
// thread: 1.5-1.9x Jacobi's solve time at 3k and 52k cells
// (docs/topics/performance.md#the-coupling-solve). A multigrid cannot repay its
// set-up per step size at a handful of iterations.
//
// Cost: one pass over the matrix and one over the vectors an iteration (the
// search direction's product is updated by the recurrence q = A z + beta q,
// so that p and q are formed in the product's pass). The matrix is kept in
// slices of kSlice rows padded to the slice's longest row, column by column
// (sliced ELLPACK, Kreutzer et al. 2014, SIAM J. Sci. Comput. 36:C401): the
// product over a slice is kSlice independent sums of a fixed length, which
// vectorise, where compressed rows of 4 to 13 entries mispredict a branch a
// row.
//
// Deterministic whatever the thread count: each row sums its entries in a
// fixed order; dot products are summed per fixed chunk of kRowsPerChunk rows
// and the chunks' sums added in chunk order.
//
// The slices are the coupling's only copy of L: the coupler's currents -L V
// come from them too (row_current), each row summed in L's column order.
//
// Split over ranks (docs/guide/parallel.md): a rank's CG holds its own rows of L
// only (each row's entries in L's order), its vectors its own cells then its
// ghosts (other ranks' cells its rows reach).
// Before each product the ghosts' entries of the vector multiplied come from
// their owners (Ranks::refresh_ghosts: one exchange an iteration), and every
// dot product and max-norm is reduced over the ranks (Ranks::reduce: the
// ranks' partial sums, each its own chunks' in chunk order, added in rank
// order; the max exact), so that every rank takes the same decisions (its
// iterations, its stop) and a number of ranks gives the same bits each run.
#pragma once

#include <Eigen/SparseCore>
#include <cstddef>
#include <string>
#include <vector>

#include "tissue/cell_numbering.hpp"

namespace fibrodem {

class CouplingCg {
 public:
  using Laplacian = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  // Iterations after which a solve that has not reached its tolerance fails
  // (the Fig. 3 scenes need at most ~20).
  static constexpr int kMaxIterations = 1000;
  static constexpr long kSlice = 8;            // rows a slice: an AVX-512 register of doubles
  static constexpr long kRowsPerChunk = 4096;  // a multiple of kSlice

  CouplingCg(const Laplacian& laplacian_nS, std::vector<double> capacitance_pF,
             int max_iterations = kMaxIterations);

  // What a rank's CG needs of the other ranks (split over ranks, above).
  class Ranks {
   public:
    virtual ~Ranks() = default;
    // Sets a vector's ghost entries (from first_ghost(), in the order of the
    // ghosts given to the constructor) to their owners' values of it.
    virtual void refresh_ghosts(double* vector) = 0;
    // Replaces this rank's partial sum by every rank's added in rank order,
    // and its largest by every rank's largest: the same bits on every rank.
    virtual void reduce(double& sum, double& largest) = 0;
  };
  // This rank's rows of the tissue's L in its held numbers
  // (junction_laplacian_nS given `held`: its own cells' rows, 0 ..
  // held.own()-1, filled; its ghosts' columns from held.own()), numbered
  // here as there, the ghosts from first_ghost(); capacitances by held cell.
  // solve() then takes and returns the own cells' potentials, in held
  // order; every rank calls it at the same point (it exchanges and reduces
  // through `ranks`), and constructs it at the same point (it takes the
  // whole tissue's largest L_ii / C_i, for the stopping test's drift
  // allowance, through `ranks`).
  CouplingCg(const Laplacian& laplacian_nS, const std::vector<double>& capacitance_pF, const CellNumbering& held,
             Ranks& ranks);
  // Where a vector's ghost entries start (split over ranks).
  long first_ghost() const { return padded_; }

  // Replaces v [mV] by x, with |x - x*|_inf <= tolerance_mV (the bound
  // above). Throws std::runtime_error if that takes more than the maximum
  // number of iterations. A v that is not finite is left as it is (its NaN or
  // infinity is the caller's to see). Returns the iterations taken.
  int solve(double* v_mV, double dt_ms, double tolerance_mV);
  // The next solve starts from v alone, not from the last solve's correction.
  void restart() { last_dt_ms_ = 0; }

  // Rows of L (cells).
  long rows() const { return n_; }
  // Row i of -L V [pA] for potentials V [mV]: the row's entries subtracted
  // one by one in column order, the diagonal among them (the order of L's
  // compressed rows), so that it is the same sum whatever the threads.
  double row_current(long i, const double* V_mV) const;
  // The same for a rank's row i (split over ranks), V by held cell:
  // cell_of_column[j] is the held cell of column j (own rows' cells, then
  // past first_ghost() the ghosts'). The same terms in the same order as
  // the whole tissue's row: the same bits.
  double row_current(long i, const double* V_mV, const int* cell_of_column) const;
  // L_ii [nS] of each cell.
  std::vector<double> diagonal_nS() const;

  struct Statistics {
    long solves = 0, iterations = 0;
    int most_iterations = 0;
  };
  const Statistics& statistics() const { return statistics_; }
  std::string describe_statistics() const;  // "1234 coupling solves, 2.10 CG iterations each (at most 9)"

 private:
  struct Sums {
    double dot = 0, largest = 0;
  };
  template <class F>
  Sums over_chunks(F&& f);
  // From x and the right-hand side's v (n_ rows): r = b - A x, z = M^-1 r (A's diagonal and M^-1 for dt),
  // p = q = 0. Returns r.z and max |r_i| / C_i.
  Sums residual(const double* v, double* x, double dt_ms);
  // q = A z + beta q, p = z + beta p; returns p.q.
  double direction(double beta);
  // sum[lane] = sum_j L_ij y_j over the off-diagonal entries of slice s's rows.
  void slice_product(long s, const double* y, double* sum) const;
  // Row i of -L V, V(j) the potential of column j.
  template <class Potential>
  double current_of_row(long i, Potential&& V) const;
  [[noreturn]] void fail(double dt_ms, double tolerance_mV, double bound_mV, int iterations) const;
  template <class CellOf>
  void take_diagonal(const Laplacian& laplacian, const std::vector<double>& capacitance_pF, CellOf&& cell_of);
  // Slices rows [0, n_): entries(i, emit) calls emit(column, weight_nS,
  // past_diagonal) on row i's off-diagonal entries, in order (past_diagonal:
  // the entry's cell comes after row i's in the tissue's numbering). Sizes the work vectors, with
  // `ghosts` entries past the padded rows.
  template <class Entries>
  void slice_rows(Entries&& entries, long ghosts);
  // Before a product over y's ghost entries; after a pass's sums (split over ranks).
  void refresh_ghosts(double* y) {
    if (ranks_) ranks_->refresh_ghosts(y);
  }

  long n_ = 0, padded_ = 0;  // rows, and rows rounded up to whole slices
  double max_rate_per_ms_ = 0;  // max_i L_ii / C_i
  int max_iterations_;
  // L's off-diagonal entries, sliced: slice s holds width_[s] columns of
  // kSlice entries from start_[s] (padding: the row itself, weight 0).
  std::vector<long> start_;
  std::vector<int> width_, column_;
  std::vector<double> weight_nS_;
  std::vector<double> diagonal_nS_, inverse_capacitance_;  // L_ii, 1/C_i
  // Per row: its entries before the padding, and how many of them come
  // before the diagonal in L's column order (row_current).
  std::vector<int> row_length_, diagonal_position_;
  // Work vectors of padded_ rows, sized once: the iterate x, r,
  // z = M^-1 r, the search direction p, q = A p (v is the caller's, which
  // solve() writes only at its end). Between solves x_ holds the last
  // solve's correction x - v, for last_dt_ms_ (0: none): the next solve
  // starts from v plus it, scaled.
  std::vector<double> x_, r_, z_, p_, q_;
  double last_dt_ms_ = 0;
  double inverse_dt_ = 0;  // 1/dt of the present solve [1/ms]
  // A's diagonal C_i/dt + L_ii and M^-1's 1/(C_i/dt + L_ii) for the present
  // dt, computed where a pass reads them rather than kept in two more
  // vectors of padded_ rows (16 bytes a cell): the divisions hide behind
  // the pass's memory traffic, and the same operations give the same bits.
  // Kept free of branches (a padding row's 1/C is 1, not 0): a branch here
  // splits a pass's loop body, and GCC then leaves r.z unfused (no FMA),
  // which moves a solve's last bits.
  double a_diagonal(long i) const { return inverse_dt_ / inverse_capacitance_[i] + diagonal_nS_[i]; }
  double inverse_diagonal(long i) const { return 1.0 / a_diagonal(i); }
  // 1/C of a padding row [1/pF]: any positive value (its r stays 0).
  static constexpr double kPaddingInverseCapacitance = 1.0;
  std::vector<double> chunk_dot_, chunk_largest_;
  Statistics statistics_;
  Ranks* ranks_ = nullptr;  // split over ranks; null in one process
};

}  // namespace fibrodem
