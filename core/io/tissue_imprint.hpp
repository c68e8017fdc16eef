// What the outputs keep of a tissue's particles once the particles are freed
// (Tissue::release_particles): rank 0 of a run split over ranks draws and
// writes the whole tissue without holding it (docs/guide/parallel.md,
// "Memory per rank"). Valid while the particles do not move (a run without
// mechanics).
//  - picture: the cell drawn at each pixel of a picture of the tissue
//    without antialiasing (the last particle covering the pixel's centre),
//    in the frame every titled picture of it has (io/picture_frame.hpp): a
//    picture drawn from it is the one drawn from the particles, byte for byte.
//  - cells: the particles' cells, run by run, for the per-particle fields.
//  - vtp: the particles' arrays of a VTK XML file, compressed once.
// On an 846,279-cell sheet (5.9 M particles) the particles and bonds take
// 237 MB, their imprint 36 MB.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "io/picture_frame.hpp"
#include "io/vtk_xml_writer.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

struct CellRaster {
  PictureFrame frame;              // of a titled picture with a colour bar: the widest
  std::vector<std::int32_t> cell;  // per pixel of frame, row by row; -1: no particle there
  std::int32_t at(int x, int y) const { return cell[static_cast<std::size_t>(y) * frame.width_px + x]; }
};

// Particles [end[k-1], end[k]) belong to cell[k] (end[-1] = 0).
struct ParticleCellRuns {
  std::vector<std::int32_t> cell, end;
  std::size_t particles() const { return end.empty() ? 0 : static_cast<std::size_t>(end.back()); }
};

struct TissueImprint {
  CellRaster picture;
  ParticleCellRuns cells;
  PackedVtpGeometry vtp;
  std::size_t bytes() const;
};

// The frame every titled picture of a tissue with these bounds has at the
// default scale (PictureOptions::height_px), with a colour bar.
PictureFrame imprint_frame(const std::array<double, 4>& bounds_um);

// An imprint made from the particles one at a time, in the tissue's order
// (TissueBuilder::for_each_particle), so that they need never be held
// together: the bounds and cell types of the tissue they make.
class TissueImprinter {
 public:
  TissueImprinter(const std::array<double, 4>& bounds_um, const std::vector<CellType>& type);
  void add(const Particle& p);
  std::shared_ptr<const TissueImprint> finish();

 private:
  const std::vector<CellType>& type_;
  std::shared_ptr<TissueImprint> imprint_;
  VtpGeometryPacker vtp_;
  std::size_t particles_ = 0;
};

// The imprint of a tissue's particles (collagen's are in no output).
std::shared_ptr<const TissueImprint> imprint_tissue(const Tissue& tissue);

}  // namespace fibrodem
