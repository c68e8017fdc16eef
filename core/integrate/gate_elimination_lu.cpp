#include "integrate/gate_elimination_lu.hpp"

#include <cmath>
#include <utility>

namespace fibrodem {

GateEliminationLu::GateEliminationLu(std::size_t n)
    : n_(n), position_(n), eliminated_(n), kept_by_gate_(n * n), lu_(n * n), pivot_(n), gate_value_(n),
      kept_rhs_(n) {
  // Every list is sized or reserved for n here, so factor() and solve() never allocate.
  for (auto* list : {&gates_, &partner_, &partner_position_, &kept_}) list->reserve(n);
  inverse_diagonal_.reserve(n);
  coupling_.reserve(n);
}

// Picks the rows to eliminate: at most one off-diagonal entry, a pivot of at
// least 1/2, and a partner column whose row is kept (so x_q is known when x_j
// is computed from it).
void GateEliminationLu::choose_rows(const double* m) {
  gates_.clear();
  partner_.clear();
  for (std::size_t j = 0; j < n_; ++j) {
    std::size_t partner = kNone, others = 0;
    for (std::size_t q = 0; q < n_ && others < 2; ++q)
      if (q != j && m[q * n_ + j] != 0.0) {
        partner = q;
        ++others;
      }
    eliminated_[j] = others < 2 && std::abs(m[j * n_ + j]) >= 0.5;
    if (eliminated_[j]) {
      gates_.push_back(j);
      partner_.push_back(partner);
    }
  }
  // A row whose partner is eliminated too is kept instead (in row order; a
  // partner only ever changes from eliminated to kept, so one pass settles it).
  std::size_t taken = 0;
  for (std::size_t g = 0; g < gates_.size(); ++g) {
    if (partner_[g] != kNone && eliminated_[partner_[g]]) {
      eliminated_[gates_[g]] = false;
      continue;
    }
    gates_[taken] = gates_[g];
    partner_[taken] = partner_[g];
    ++taken;
  }
  gates_.resize(taken);
  partner_.resize(taken);
  kept_.clear();
  for (std::size_t j = 0; j < n_; ++j) {
    position_[j] = eliminated_[j] ? kNone : kept_.size();
    if (!eliminated_[j]) kept_.push_back(j);
  }
}

bool GateEliminationLu::factor(const double* m) {
  choose_rows(m);
  const std::size_t k = kept_.size();
  inverse_diagonal_.clear();
  coupling_.clear();
  partner_position_.clear();
  for (std::size_t g = 0; g < gates_.size(); ++g) {
    const std::size_t j = gates_[g], q = partner_[g];
    inverse_diagonal_.push_back(1.0 / m[j * n_ + j]);
    coupling_.push_back(q == kNone ? 0.0 : m[q * n_ + j]);
    partner_position_.push_back(q == kNone ? kNone : position_[q]);
    for (std::size_t p = 0; p < k; ++p) kept_by_gate_[g * k + p] = m[j * n_ + kept_[p]];
  }
  // S = M_KK, then each eliminated row folds into its partner's column.
  for (std::size_t c = 0; c < k; ++c)
    for (std::size_t p = 0; p < k; ++p) lu_[c * k + p] = m[kept_[c] * n_ + kept_[p]];
  for (std::size_t g = 0; g < gates_.size(); ++g) {
    if (partner_position_[g] == kNone) continue;
    const double scale = coupling_[g] * inverse_diagonal_[g];
    double* column = &lu_[partner_position_[g] * k];
    const double* from = &kept_by_gate_[g * k];
    for (std::size_t p = 0; p < k; ++p) column[p] -= from[p] * scale;
  }
  return factor_kept_block();
}

// In-place LU with partial pivoting of the k x k Schur complement (rows swapped
// whole, as LAPACK's getrf does).
bool GateEliminationLu::factor_kept_block() {
  const std::size_t k = kept_.size();
  double* a = lu_.data();
  for (std::size_t c = 0; c < k; ++c) {
    double* column = a + c * k;
    std::size_t best = c;
    for (std::size_t i = c + 1; i < k; ++i)
      if (std::abs(column[i]) > std::abs(column[best])) best = i;
    if (column[best] == 0.0) return false;
    pivot_[c] = best;
    if (best != c)
      for (std::size_t j = 0; j < k; ++j) std::swap(a[j * k + c], a[j * k + best]);
    const double inverse = 1.0 / column[c];
    for (std::size_t i = c + 1; i < k; ++i) column[i] *= inverse;
    for (std::size_t j = c + 1; j < k; ++j) {
      double* __restrict target = a + j * k;
      const double f = target[c];
      if (f == 0.0) continue;
      const double* __restrict l = column;
      for (std::size_t i = c + 1; i < k; ++i) target[i] -= f * l[i];
    }
  }
  return true;
}

void GateEliminationLu::solve_kept_block(double* r) const {
  const std::size_t k = kept_.size();
  const double* a = lu_.data();
  for (std::size_t c = 0; c < k; ++c)
    if (pivot_[c] != c) std::swap(r[c], r[pivot_[c]]);
  for (std::size_t c = 0; c < k; ++c) {  // L (unit diagonal)
    const double rc = r[c];
    if (rc == 0.0) continue;
    const double* l = a + c * k;
    for (std::size_t i = c + 1; i < k; ++i) r[i] -= rc * l[i];
  }
  for (std::size_t c = k; c-- > 0;) {  // U
    const double* u = a + c * k;
    r[c] /= u[c];
    const double rc = r[c];
    for (std::size_t i = 0; i < c; ++i) r[i] -= rc * u[i];
  }
}

void GateEliminationLu::solve(double* x) const {
  const std::size_t k = kept_.size();
  // Each gate's unknown as if x_q were 0, and its share of the kept rows.
  for (std::size_t p = 0; p < k; ++p) kept_rhs_[p] = x[kept_[p]];
  for (std::size_t g = 0; g < gates_.size(); ++g) {
    const double w = x[gates_[g]] * inverse_diagonal_[g];
    gate_value_[g] = w;
    if (w == 0.0) continue;
    const double* column = &kept_by_gate_[g * k];
    for (std::size_t p = 0; p < k; ++p) kept_rhs_[p] -= column[p] * w;
  }
  solve_kept_block(kept_rhs_.data());
  for (std::size_t p = 0; p < k; ++p) x[kept_[p]] = kept_rhs_[p];
  // Then the gates from their partners' values.
  for (std::size_t g = 0; g < gates_.size(); ++g) {
    const std::size_t q = partner_position_[g];
    const double x_q = q == kNone ? 0.0 : kept_rhs_[q];
    x[gates_[g]] = gate_value_[g] - inverse_diagonal_[g] * coupling_[g] * x_q;
  }
}

}  // namespace fibrodem
