// A tissue as a VTK XML PolyData file (.vtp; ParaView opens it): the same
// points, vertices, lines and arrays as the legacy file (io/vtk_writer.hpp),
// in binary, zlib-compressed appended data (the VTK XML file format:
// header_type UInt64, compressor vtkZLibDataCompressor, raw encoding).
//
// Types: point coordinates, radius_um, the per-cell fields and the
// displacement are Float32 (7 significant digits: a 50 mm sheet's
// coordinates to ~4 nm, V to ~1e-5 mV; the exact values stay in the CSV
// files); `cell` and the vertex/line indices Int32; `cell_type` UInt8.
#pragma once

#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "io/vtk_writer.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

// Throws std::runtime_error if the file cannot be written, a field does not
// hold one value per cell, or the tissue has more particles than Int32
// indexes. Field names have spaces replaced by '_'. The first field, if any,
// is the points' active scalars (ParaView colours by it), else cell_type.
// A tissue whose particles were released with an imprint
// (io/tissue_imprint.hpp) is written from it, the same bytes: without
// bonds or displacement (std::logic_error if asked for).
void write_tissue_vtp(const Tissue& tissue, const std::filesystem::path& file,
                      const CellFields& cell_fields = {}, bool with_bonds = true,
                      const std::vector<std::array<double, 2>>* displacement_um = nullptr);

// One array of the file as written: its XML element up to its offset, and
// its appended data (block header and deflated blocks).
struct PackedVtpArray {
  std::string element_head;
  std::vector<unsigned char> appended;
};
// What every file of a tissue holds the same whatever its fields and that
// only the particles give: their radius_um, cell, cell_type and points.
// (The vertices are numbered 0, 1, ...: packed afresh.)
struct PackedVtpGeometry {
  PackedVtpArray radius, cell, cell_type, points;
  std::size_t bytes() const;
};
// The geometry packed as the particles come, one at a time in the tissue's
// order, so that they need never be held together (an imprint made while
// the tissue is built: io/tissue_imprint.hpp).
class VtpGeometryPacker {
 public:
  VtpGeometryPacker();
  ~VtpGeometryPacker();
  void add(const Particle& p, CellType type);
  PackedVtpGeometry finish();

 private:
  class ArrayPacker;
  std::unique_ptr<ArrayPacker> radius_, cell_, cell_type_, points_;
};

}  // namespace fibrodem
