#include "coupling/gap_junction.hpp"

#include <algorithm>
#include <stdexcept>

#include "model/work_split.hpp"

namespace fibrodem {

GapJunctionCoupler::GapJunctionCoupler(const Tissue& tissue, double D_m_nS, double D_f_nS,
                                       std::vector<double> capacitance_pF)
    : capacitance_pF_(std::move(capacitance_pF)) {
  const auto n = static_cast<Eigen::Index>(tissue.cell_count());
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(4 * tissue.cell_edges.size() + tissue.cell_count());
  for (const auto& [i, j] : tissue.cell_edges) {
    const bool both_myocytes =
        tissue.type[i] == CellType::myocyte && tissue.type[j] == CellType::myocyte;
    const double g = both_myocytes ? D_m_nS : D_f_nS;
    if (g == 0.0) continue;
    entries.emplace_back(i, i, g);
    entries.emplace_back(j, j, g);
    entries.emplace_back(i, j, -g);
    entries.emplace_back(j, i, -g);
  }
  laplacian_.resize(n, n);
  laplacian_.setFromTriplets(entries.begin(), entries.end());
  laplacian_.makeCompressed();
  rhs_.resize(n);
}

// Row `row` of -L V: each row sums in a fixed order, whatever the threads.
double GapJunctionCoupler::row_current(Eigen::Index row, const double* V) const {
  double current = 0.0;
  for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(laplacian_, row); it; ++it)
    current -= it.value() * V[it.col()];
  return current;
}

void GapJunctionCoupler::add_current(const double* V, double* i_ext) const {
  for_each_cell(laplacian_.outerSize(), [&](Eigen::Index row) { i_ext[row] += row_current(row, V); });
}

void GapJunctionCoupler::current_into(const double* V, const int* cells, std::size_t count, double* current) const {
  for (std::size_t k = 0; k < count; ++k) current[k] = row_current(cells[k], V);
}

const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& GapJunctionCoupler::factorisation(double dt_ms) {
  for (const auto& f : factorisations_)
    if (f.dt_ms == dt_ms) return *f.ldlt;
  if (factorisations_.size() >= kMaxFactorisations) factorisations_.erase(factorisations_.begin());
  const Eigen::Index n = laplacian_.rows();
  Eigen::SparseMatrix<double> system = laplacian_;
  for (Eigen::Index i = 0; i < n; ++i) system.coeffRef(i, i) += capacitance_pF_[i] / dt_ms;
  auto ldlt = std::make_unique<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>(system);
  if (ldlt->info() != Eigen::Success) throw std::runtime_error("gap-junction coupling: factorising C/dt + L failed");
  factorisations_.push_back({dt_ms, std::move(ldlt)});
  return *factorisations_.back().ldlt;
}

void GapJunctionCoupler::implicit_step(double* V, double dt_ms) {
  const Eigen::Index n = laplacian_.rows();
  const auto& ldlt = factorisation(dt_ms);
  for (Eigen::Index i = 0; i < n; ++i) rhs_[i] = capacitance_pF_[i] / dt_ms * V[i];
  solution_ = ldlt.solve(rhs_);  // (sized once: no allocation per step)
  std::copy(solution_.data(), solution_.data() + n, V);
}

std::vector<double> GapJunctionCoupler::total_conductance_nS() const {
  std::vector<double> total(static_cast<std::size_t>(laplacian_.rows()), 0.0);
  for (Eigen::Index row = 0; row < laplacian_.outerSize(); ++row)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(laplacian_, row); it; ++it)
      if (it.col() == row) total[static_cast<std::size_t>(row)] = it.value();
  return total;
}

double GapJunctionCoupler::max_rate_per_ms() const {
  const std::vector<double> total = total_conductance_nS();
  double rate = 0.0;
  for (std::size_t i = 0; i < total.size(); ++i) rate = std::max(rate, 2.0 * total[i] / capacitance_pF_[i]);
  return rate;
}

}  // namespace fibrodem
