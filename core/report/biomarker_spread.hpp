// biomarkers.csv (one row per cell and beat) summed up per cell type: count,
// mean, SD, min and max of each biomarker (the mean is summary.json's
// mean_biomarkers: every cell-beat recorded), and their histograms.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "io/csv_table.hpp"
#include "io/plot_png.hpp"

namespace fibrodem {

// The columns of biomarkers.csv summed up, in this order.
inline const std::vector<std::string> kBiomarkerColumns = {"apd90_ms", "rmp_mV", "apo_mV", "dvdt_max_mV_per_ms"};

struct BiomarkerSpread {
  std::string type, metric;
  std::size_t n = 0;  // finite values
  double mean = 0, sd = 0, min = 0, max = 0;  // NaN without values (sd: with fewer than 2)
};

std::vector<BiomarkerSpread> biomarker_spread(const CsvTable& biomarkers);

// One panel per cell type and biomarker: a step-line histogram on the
// type's own range (Sturges' rule: ceil(log2 n) + 1 bins).
std::vector<PlotPanel> biomarker_histograms(const CsvTable& biomarkers);

// cell index -> type, from the cell and type columns.
std::map<int, std::string> cell_types(const CsvTable& biomarkers);

}  // namespace fibrodem
