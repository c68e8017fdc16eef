// biomarkers.csv (one row per cell and beat) summed up per cell type: count,
// mean, SD, min and max of each biomarker over the cell-beats that fired (the
// mean is summary.json's mean_biomarkers), their histograms, and how many
// cell-beats did not fire (an empty activation_ms).
//
// The file is read twice, row by row, and never held: the first pass finds
// each type's and biomarker's count, sum, min and max, the second the squared
// deviations from the mean (the two-pass SD of measure/sample_statistics) and
// the histogram counts on the range of the first. The report's memory does not
// grow with the tissue (a row held as text takes ~600 bytes a cell-beat).
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <set>
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

// The rows of biomarkers.csv, given in two passes of the same rows
// (first_pass over all of them, then second_pass over all of them).
class BiomarkerDigest {
 public:
  // `typed_cells`: the cells whose type types() is to give (the traced ones).
  BiomarkerDigest(const std::vector<std::string>& header, std::set<int> typed_cells = {});
  void first_pass(const std::vector<std::string>& row);
  void second_pass(const std::vector<std::string>& row);

  std::size_t rows() const { return rows_; }
  // Per type (in order of first appearance) and biomarker present.
  std::vector<BiomarkerSpread> spread() const;
  // One panel per type and biomarker with values: a step-line histogram on
  // the type's own range (Sturges' rule: ceil(log2 n) + 1 bins).
  std::vector<PlotPanel> histograms() const;
  // cell index -> type, of the typed cells found.
  const std::map<int, std::string>& types() const { return types_; }
  // Per type (in order of first appearance), the cell-beats that did not fire.
  std::vector<std::pair<std::string, std::size_t>> not_fired() const;

 private:
  struct Tally {
    std::size_t n = 0;
    double sum = 0, squares = 0, lo = 0, hi = 0;
    std::vector<double> count;  // per bin, from the second pass
    double bin_lo = 0, bin_hi = 0, bin_width = 0;
  };
  std::size_t type_index(const std::string& type);
  bool fired(const std::vector<std::string>& row) const;  // a row without activation did not
  Tally& tally(std::size_t type, std::size_t metric) { return tallies_[type * columns_.size() + metric]; }
  const Tally& tally(std::size_t type, std::size_t metric) const { return tallies_[type * columns_.size() + metric]; }

  std::optional<std::size_t> type_column_, cell_column_, activation_column_;
  std::vector<std::pair<std::string, std::size_t>> columns_;  // biomarker present, its column
  std::vector<std::string> types_seen_;
  std::vector<std::size_t> not_fired_;  // per type seen
  std::vector<Tally> tallies_;  // type-major
  std::set<int> typed_cells_;
  std::map<int, std::string> types_;
  std::size_t rows_ = 0;
  bool binned_ = false;
};

// biomarkers.csv read in two passes (nullopt if it cannot be read or has no
// header line).
std::optional<BiomarkerDigest> digest_biomarkers_csv(const std::filesystem::path& file,
                                                     const std::set<int>& typed_cells);

}  // namespace fibrodem
