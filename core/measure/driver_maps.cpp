#include "measure/driver_maps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "io/csv_writer.hpp"

namespace fibrodem {

HighestFrequencySite highest_frequency_site(const Tissue& tissue, const std::vector<double>& per_cell_hz) {
  HighestFrequencySite site;
  site.frequency_hz = -std::numeric_limits<double>::infinity();
  for (double f : per_cell_hz)
    if (std::isfinite(f)) site.frequency_hz = std::max(site.frequency_hz, f);
  if (!std::isfinite(site.frequency_hz)) {
    site.frequency_hz = std::numeric_limits<double>::quiet_NaN();
    return site;
  }
  // Frequencies are bins k / T computed alike: equal ones are equal bits.
  for (std::size_t c = 0; c < per_cell_hz.size(); ++c) {
    if (per_cell_hz[c] != site.frequency_hz) continue;
    ++site.cells;
    site.x_mm += tissue.x_um[c] / 1000.0;
    site.y_mm += tissue.y_um[c] / 1000.0;
  }
  site.x_mm /= static_cast<double>(site.cells);
  site.y_mm /= static_cast<double>(site.cells);
  return site;
}

std::size_t PsDensityGrid::bin_of(double x_mm, double y_mm) const {
  const int i = std::clamp(static_cast<int>(std::floor((x_mm - x0_mm) / bin_mm)), 0, nx - 1);
  const int j = std::clamp(static_cast<int>(std::floor((y_mm - y0_mm) / bin_mm)), 0, ny - 1);
  return static_cast<std::size_t>(j) * nx + i;
}

std::vector<double> PsDensityGrid::per_cell_per_cm2(const Tissue& tissue) const {
  std::vector<double> out(tissue.cell_count());
  for (std::size_t c = 0; c < out.size(); ++c)
    out[c] = ps_seconds[bin_of(tissue.x_um[c] / 1000.0, tissue.y_um[c] / 1000.0)] / bin_area_cm2();
  return out;
}

PsDensityGrid ps_density(const std::vector<SingularityTrack>& tracks, const std::array<double, 4>& bounds_mm,
                         double bin_mm, double every_ms) {
  if (!(bin_mm > 0)) throw std::invalid_argument("PS density: bin_mm must be > 0, got " + format_number(bin_mm));
  PsDensityGrid grid;
  grid.x0_mm = bounds_mm[0];
  grid.y0_mm = bounds_mm[2];
  grid.bin_mm = bin_mm;
  // At least one bin; a tissue a whole number of bins wide gets exactly that many.
  auto bins_across = [bin_mm](double from, double to) {
    return std::max(1, static_cast<int>(std::ceil((to - from) / bin_mm - 1e-9)));
  };
  grid.nx = bins_across(bounds_mm[0], bounds_mm[1]);
  grid.ny = bins_across(bounds_mm[2], bounds_mm[3]);
  grid.ps_seconds.assign(static_cast<std::size_t>(grid.nx) * grid.ny, 0.0);
  for (const auto& track : tracks)
    for (const auto& p : track.trajectory) grid.ps_seconds[grid.bin_of(p.x_mm, p.y_mm)] += every_ms / 1000.0;
  return grid;
}

void write_ps_density_csv(const std::filesystem::path& file, const PsDensityGrid& grid) {
  CsvWriter csv(file, {"x_mm", "y_mm", "ps_seconds", "ps_seconds_per_cm2"});
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i) {
      const double s = grid.ps_seconds[static_cast<std::size_t>(j) * grid.nx + i];
      csv.cell(grid.x0_mm + (i + 0.5) * grid.bin_mm).cell(grid.y0_mm + (j + 0.5) * grid.bin_mm).cell(s)
          .cell(s / grid.bin_area_cm2());
      csv.end_row();
    }
  csv.flush();
}

double rotor_time_fraction(const std::vector<SpiralMeasures>& spirals, const std::vector<double>& sample_times_ms) {
  if (sample_times_ms.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::size_t with_rotor = 0;
  for (double t : sample_times_ms)
    with_rotor += std::any_of(spirals.begin(), spirals.end(),
                              [t](const SpiralMeasures& s) { return s.rotor && s.birth_ms <= t && t <= s.death_ms; });
  return static_cast<double>(with_rotor) / static_cast<double>(sample_times_ms.size());
}

}  // namespace fibrodem
