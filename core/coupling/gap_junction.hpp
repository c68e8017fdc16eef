// Gap-junction coupling on the cell graph (seed paper eq. 4-5):
//   I_n,c = sum_i D^i (V_i - V_c),
// D = D_m between two myocytes joined end to end, D_m_side between two side
// by side (tissue/tissue.hpp end_to_end) and D_f for any pair with a
// fibroblast (coupling/coupling_region.hpp: by region where the manifest
// gives regions; times coupling/coupling_field.hpp's map where it gives
// one), as the graph Laplacian L [nS]: the currents are -L V and the backward-Euler step
// solves (C/dt + L) V' = (C/dt) V, by preconditioned conjugate gradients
// (coupling/coupling_cg.hpp), which hold L for both.
#pragma once

#include <string>
#include <vector>

#include "coupling/coupler.hpp"
#include "coupling/coupling_cg.hpp"
#include "coupling/coupling_field.hpp"
#include "coupling/coupling_region.hpp"
#include "tissue/cell_numbering.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

// Where the coupling's regions and map hold the tissue's junctions, counted
// junction by junction: a region or the map that holds none of them is a
// ManifestError naming it (check), so that one off the tissue is seen at
// once. (junction_laplacian_nS counts and checks a tissue holding its
// whole graph; a rank holding part of it counts every edge as it goes by.)
// Where a junction lies: the last region holding its midpoint (-1: none),
// whether the map holds it, and the midpoint (0, 0 where neither regions
// nor a map are given).
struct JunctionPlace {
  int region = -1;
  bool in_field = false;
  double x_um = 0, y_um = 0;
};

class CouplingPlaces {
 public:
  CouplingPlaces(const std::vector<CouplingRegion>& regions, const CouplingField* field);
  // The place of the junction of cells i and j, counted.
  JunctionPlace count(const Tissue& tissue, int i, int j);
  JunctionPlace count(const CellCentre& i, const CellCentre& j);
  void check(const Tissue& tissue) const;

 private:
  const std::vector<CouplingRegion>& regions_;
  const CouplingField* field_;
  std::vector<long> junctions_held_;
  long junctions_in_field_ = 0;
};

// L [nS] of the tissue's junctions, every cell a row. Given `held` (a
// rank's cells split over ranks, tissue/cell_numbering.hpp), L is in its
// held numbers and only the own cells' rows are filled; each row's entries
// are in the tissue's column order. Regions and the map are checked against
// every junction of the tissue (CouplingPlaces), so that a region that
// holds none is the same error on every rank.
CouplingCg::Laplacian junction_laplacian_nS(const Tissue& tissue, const JunctionConductances& g_nS,
                                            const std::vector<CouplingRegion>& regions = {},
                                            const CouplingField* field = nullptr, const CellNumbering* held = nullptr);

class GapJunctionCoupler final : public Coupler {
 public:
  // `regions` override g_nS where they hold a junction's midpoint, and
  // `field` (if any) scales what they give; a region or field that holds no
  // junction is a ManifestError naming it.
  GapJunctionCoupler(const Tissue& tissue, const JunctionConductances& g_nS, std::vector<double> capacitance_pF,
                     const std::vector<CouplingRegion>& regions = {}, const CouplingField* field = nullptr);
  void add_current(const double* V_mV, double* i_ext_pA) const override;
  void current_into(const double* V_mV, const int* cells, std::size_t count, double* current_pA) const override;
  void implicit_step(double* V_mV, double dt_ms, double tolerance_mV) override;
  void restart_implicit() override { cg_.restart(); }
  std::string describe_solves() const override;
  double max_rate_per_ms() const override;
  std::vector<double> total_conductance_nS() const override;

 private:
  CouplingCg cg_;
  double max_rate_per_ms_;  // (from the capacitances, which the CG keeps only as 1/C)
};

}  // namespace fibrodem
