#include "run/tissue_snapshots.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "io/tissue_picture.hpp"
#include "io/pvd_collection.hpp"
#include "io/vtk_writer.hpp"
#include "io/vtk_xml_writer.hpp"

namespace fibrodem {

namespace {

// dir/stem.vtk or dir/stem.vtp, as vtk_format asks; returns the file's name.
std::string write_vtk_file(const std::string& vtk_format, const Tissue& tissue, const std::filesystem::path& dir,
                           const std::string& stem, const CellFields& fields, bool with_bonds,
                           const std::vector<std::array<double, 2>>* displacement_um = nullptr) {
  const bool xml = vtk_format == "xml";
  const std::string name = stem + (xml ? ".vtp" : ".vtk");
  if (xml) write_tissue_vtp(tissue, dir / name, fields, with_bonds, displacement_um);
  else write_tissue_vtk(tissue, dir / name, fields, with_bonds, displacement_um);
  return name;
}

// strain_<t>_ms.png: the deformed tissue coloured by its cells' fibre strain
// E_yy, the colour bar spanning the frame's 2nd to 98th percentile (a few
// cells at the sheet's edges, strained far less or more than the rest,
// would otherwise take the whole range); cells without a strain (too few
// neighbours) grey, and counted in the title.
void write_strain_png(const std::filesystem::path& dir, const std::string& scene_name, const SnapshotFrame& frame) {
  std::vector<double> finite;
  for (double e : frame.strain.E_yy)
    if (std::isfinite(e)) finite.push_back(e);
  const std::size_t unresolved = frame.strain.E_yy.size() - finite.size();
  PictureOptions picture;
  picture.value_label = "fibre strain E_yy";
  picture.title = fmt::format("{}   t = {:.1f} ms", scene_name, frame.t_ms);
  if (unresolved > 0)
    picture.title += fmt::format(" ({} cell{} without a strain, grey)", unresolved, unresolved == 1 ? "" : "s");
  if (!finite.empty()) {
    const auto at = [&](double q) {
      auto k = finite.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(finite.size() - 1));
      std::nth_element(finite.begin(), k, finite.end());
      return *k;
    };
    picture.value_min = at(0.02);
    picture.value_max = at(0.98);
  }
  picture.pixels_per_um = frame.pixels_per_um;
  picture.antialias = false;
  char name[64];
  std::snprintf(name, sizeof name, "strain_%09.3f_ms.png", frame.t_ms);
  write_tissue_png(*frame.now, dir / name, &frame.strain.E_yy, picture);
}

}  // namespace

void write_tissue_overview(const std::filesystem::path& dir, const std::string& scene_name, const Tissue& tissue,
                           const std::string& vtk_format) {
  PictureOptions picture;
  picture.title = scene_name + ": " + std::to_string(tissue.count(CellType::myocyte)) + " myocytes, " +
                  std::to_string(tissue.count(CellType::fibroblast)) + " fibroblasts";
  write_tissue_png(tissue, dir / "tissue.png", nullptr, picture);
  write_vtk_file(vtk_format, tissue, dir, "tissue", {}, true);
}

Tissue present_tissue(const Tissue& tissue, const MechanicsSolver* mechanics,
                      std::vector<std::array<double, 2>>* displacement) {
  Tissue now = tissue;
  if (!mechanics) return now;
  now.particles = mechanics->particles();
  if (displacement)
    for (std::size_t p = 0; p < now.particles.size(); ++p)
      displacement->push_back({now.particles[p].x_um - tissue.particles[p].x_um,
                               now.particles[p].y_um - tissue.particles[p].y_um});
  return now;
}

SnapshotFrame take_snapshot(double t, const SnapshotSpec& spec, const std::shared_ptr<const Tissue>& tissue,
                            const MechanicsSolver* mechanics, const std::vector<double>& V_mV,
                            const CellStrainField* strain) {
  SnapshotFrame frame;
  frame.t_ms = t;
  frame.now = mechanics ? std::make_shared<const Tissue>(present_tissue(
                              *tissue, mechanics, spec.vtk ? &frame.displacement : nullptr))
                        : tissue;
  frame.V_mV = V_mV;
  if (strain) frame.strain = *strain;
  // The scale of the undeformed tissue, so that every snapshot shows the
  // deformation at the same magnification.
  const auto box = tissue->bounds_um();
  frame.pixels_per_um = PictureOptions{}.height_px / std::max(box[3] - box[2], 1.0);
  return frame;
}

void write_snapshot(const std::filesystem::path& dir, const SnapshotSpec& spec, const std::string& vtk_format,
                    const std::string& scene_name, const SnapshotFrame& frame) {
  char stem[64];
  std::snprintf(stem, sizeof stem, "snapshot_%09.3f_ms", frame.t_ms);
  if (spec.png) {
    PictureOptions picture;
    picture.value_label = "V (mV)";
    picture.value_min = -90;
    picture.value_max = 40;
    picture.title = fmt::format("{}   t = {:.1f} ms", scene_name, frame.t_ms);
    picture.pixels_per_um = frame.pixels_per_um;
    picture.antialias = false;  // one picture per frame: the cheap kind
    write_tissue_png(*frame.now, dir / (std::string(stem) + ".png"), &frame.V_mV, picture);
  }
  const CellStrainField& strain = frame.strain;
  if (spec.strain && !strain.E_yy.empty()) write_strain_png(dir, scene_name, frame);
  if (spec.vtk) {
    CellFields fields{{"V_mV", frame.V_mV}};
    if (!strain.E_yy.empty())
      fields.insert(fields.end(), {{"E_xx", strain.E_xx}, {"E_yy", strain.E_yy}, {"E_xy", strain.E_xy},
                                   {"fibre_stretch", strain.fibre_stretch}, {"max_shear", strain.max_shear}});
    const std::string name = write_vtk_file(vtk_format, *frame.now, dir, stem, fields, false,
                                            frame.displacement.empty() ? nullptr : &frame.displacement);
    // Listed once written: the collection names only whole files.
    if (vtk_format == "xml") add_to_pvd(dir / kSnapshotCollection, frame.t_ms, name);
  }
}

void write_maps(const std::filesystem::path& dir, const std::string& scene_name, const Tissue& tissue,
                const std::vector<BeatBiomarkers>& beats, const std::string& vtk_format) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> activation(tissue.cell_count(), nan), apd90 = activation, rmp = activation, apo = activation;
  std::vector<char> not_fired_last(tissue.cell_count(), 0);
  for (const auto& b : beats) {
    not_fired_last[b.cell] = !fired(b);
    activation[b.cell] = b.activation_ms;
    apd90[b.cell] = b.apd90_ms;
    rmp[b.cell] = b.rmp_mV;
    apo[b.cell] = b.apo_mV;
  }
  // Cells whose last beat did not fire have no activation: drawn grey, and counted in the title.
  const auto not_fired = std::count(not_fired_last.begin(), not_fired_last.end(), 1);
  PictureOptions picture;
  picture.value_label = "activation (ms)";
  picture.title = scene_name + ": activation map, last beat";
  if (not_fired > 0) picture.title += fmt::format(" ({} cells not fired, grey)", not_fired);
  write_tissue_png(tissue, dir / "activation_map.png", &activation, picture);
  // (The maps move into the file's fields: each is held once, 8 bytes a cell.)
  CellFields fields;
  fields.emplace_back("activation_ms", std::move(activation));
  fields.emplace_back("apd90_ms", std::move(apd90));
  fields.emplace_back("rmp_mV", std::move(rmp));
  fields.emplace_back("apo_mV", std::move(apo));
  write_vtk_file(vtk_format, tissue, dir, "maps", fields, false);
}

}  // namespace fibrodem
