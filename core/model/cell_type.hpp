// The kinds of cell a tissue holds; each kind has its own population of
// model instances (model/population.hpp) and its own models in a manifest.
#pragma once

#include <array>
#include <cstdint>

namespace fibrodem {

// (A byte: a tissue holds one a cell.)
enum class CellType : std::uint8_t { myocyte = 0, fibroblast = 1 };
inline constexpr std::array<const char*, 2> kCellTypeNames = {"myocyte", "fibroblast"};
inline const char* cell_type_name(CellType t) { return kCellTypeNames[static_cast<int>(t)]; }

}  // namespace fibrodem
