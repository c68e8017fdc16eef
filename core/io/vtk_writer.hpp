// A tissue as a legacy-VTK ASCII PolyData file (.vtk; ParaView opens it):
// particles as points (coordinates in um, z = 0) with point data `radius_um`,
// `cell`, `cell_type` (0 myocyte, 1 fibroblast) and each named per-cell field
// mapped to the cell's particles; bonds as lines. In ParaView, show the points
// with the "Point Gaussian" representation, scale by `radius_um`.
#pragma once

#include <array>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "tissue/tissue.hpp"

namespace fibrodem {

using CellFields = std::vector<std::pair<std::string, std::vector<double>>>;

// Throws std::runtime_error if the file cannot be written or a field does not
// hold one value per cell. Field names have spaces replaced by '_'.
// `displacement_um`, if given, is one (dx, dy) per particle, written as a vector.
void write_tissue_vtk(const Tissue& tissue, const std::filesystem::path& file,
                      const CellFields& cell_fields = {}, bool with_bonds = true,
                      const std::vector<std::array<double, 2>>* displacement_um = nullptr);

}  // namespace fibrodem
