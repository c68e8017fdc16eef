// Direct solver for CVODE's Newton matrix M = I - gamma J of a few cells,
// exploiting the shape cell models give it.
//
// A gate's rate depends on its own value and on V alone (StateInfo::voltage_only;
// some also on one concentration, like CRN's f_Ca on Ca_i), so row j of M has
// only two entries: the diagonal M_jj = 1 - gamma b_j and one column q (V).
// Such a row gives its unknown directly once x_q is known,
//     x_j = (r_j - M_jq x_q) / M_jj,
// so it is eliminated before any dense work: the remaining ("kept") rows form a
// smaller dense system, the Schur complement
//     S = M_KK - sum_j M_Kj (M_jq / M_jj) e_q^T,
// factored by LU with partial pivoting. On one CRN 1998 cell 5 to 8 of its 21
// rows are kept (LU cost <= 8^3 instead of 21^3); Ni 2017 keeps 10 to 12 of 27.
//
// The structure is read from M's entries at every factorisation (exact zeros
// off the row's pair), so nothing is assumed of the model: a row that does not
// have the shape is simply kept. The algebra is exact, the same system as a
// full LU solves; only the order of elimination differs. An eliminated row's
// pivot M_jj must be at least 1/2 (for a decaying state it is >= 1), so the
// pivots taken without search are never small.
#pragma once

#include <cstddef>
#include <vector>

namespace fibrodem {

class GateEliminationLu {
 public:
  explicit GateEliminationLu(std::size_t n);

  // Factors the n x n matrix m (column-major, m[j * n + i] = M_ij); false if
  // the kept block is singular.
  bool factor(const double* m);
  // x <- M^-1 x.
  void solve(double* x) const;

  std::size_t size() const { return n_; }
  std::size_t eliminated() const { return gates_.size(); }

 private:
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  void choose_rows(const double* m);
  bool factor_kept_block();
  void solve_kept_block(double* r) const;

  std::size_t n_;
  // Eliminated rows: the row, its one off-diagonal column (kNone: none), that
  // column's place among the kept rows, 1 / M_jj and M_jq.
  std::vector<std::size_t> gates_, partner_, partner_position_;
  std::vector<double> inverse_diagonal_, coupling_;
  // Kept rows in order, and each state's place among them (kNone: eliminated).
  std::vector<std::size_t> kept_, position_;
  std::vector<char> eliminated_;  // per row, while choosing
  // M_Kj for each eliminated j (a column of kept_.size() entries per gate).
  std::vector<double> kept_by_gate_;
  // The Schur complement's LU factors (column-major) and row pivots.
  std::vector<double> lu_;
  std::vector<std::size_t> pivot_;
  mutable std::vector<double> gate_value_, kept_rhs_;  // solve() scratch
};

}  // namespace fibrodem
