// Gap-junction coupling on the cell graph (seed paper eq. 4-5):
//   I_n,c = sum_i D^i (V_i - V_c),
// D = D_m between two myocytes and D_f for any pair with a fibroblast. Stored
// as the graph Laplacian L [nS] (Eigen sparse, row-major) so that the currents
// are -L V and the backward-Euler step solves (C/dt + L) V' = (C/dt) V.
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <memory>
#include <optional>
#include <vector>

#include "coupling/coupler.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

class GapJunctionCoupler final : public Coupler {
 public:
  GapJunctionCoupler(const Tissue& tissue, double D_m_nS, double D_f_nS,
                     std::vector<double> capacitance_pF);

  void add_current(const double* V_mV, double* i_ext_pA) const override;
  void current_into(const double* V_mV, const int* cells, std::size_t count, double* current_pA) const override;
  void implicit_step(double* V_mV, double dt_ms) override;
  double max_rate_per_ms() const override;
  std::vector<double> total_conductance_nS() const override;

  const Eigen::SparseMatrix<double, Eigen::RowMajor>& laplacian_nS() const { return laplacian_; }

 private:
  double row_current(Eigen::Index row, const double* V_mV) const;
  Eigen::SparseMatrix<double, Eigen::RowMajor> laplacian_;
  std::vector<double> capacitance_pF_;
  // Factorisations of C/dt + L, one per dt met (an adaptive run meets a
  // dozen: its steps are powers of two times a quantum), the oldest dropped
  // beyond kMaxFactorisations (a run whose steps are off any grid).
  struct Factorisation {
    double dt_ms = 0;
    std::unique_ptr<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>> ldlt;
  };
  static constexpr std::size_t kMaxFactorisations = 24;
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& factorisation(double dt_ms);
  std::vector<Factorisation> factorisations_;
  Eigen::VectorXd rhs_, solution_;
};

}  // namespace fibrodem
