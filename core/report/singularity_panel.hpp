// phase_singularities.csv (output.reentry) as a plot panel: each tracked
// phase singularity's trajectory in the tissue's plane, x and y in mm, the
// longest-lived kMostSeriesPerPanel tracks drawn (the title says how many
// there are), labelled with their id and chirality.
#pragma once

#include <optional>

#include "io/csv_table.hpp"
#include "io/plot_png.hpp"

namespace fibrodem {

// nullopt if the table lacks the columns or has no row.
std::optional<PlotPanel> singularity_trajectories(const CsvTable& table);

}  // namespace fibrodem
