// Pictures (PNG) and ParaView files (VTK) of the tissue: by cell type at the
// start (output.tissue_picture), coloured by V during the run
// (output.snapshots) and as per-cell maps of the last beat at the end
// (output.maps). The ParaView files are legacy ASCII (.vtk) or, with
// vtk_format "xml", binary compressed VTK XML (.vtp) with the snapshots
// listed in the time collection snapshots.pvd (output.vtk_format).
#pragma once

#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "measure/biomarkers.hpp"
#include "measure/cell_strain.hpp"
#include "mechanics/mechanics_solver.hpp"
#include "scene/scene.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

// The snapshots' time collection, in the run's folder.
inline constexpr const char* kSnapshotCollection = "snapshots.pvd";

// tissue.png (by cell type) and tissue.vtk (.vtp) in dir.
void write_tissue_overview(const std::filesystem::path& dir, const std::string& scene_name, const Tissue& tissue,
                           const std::string& vtk_format);

// The tissue as it is now: deformed particles when mechanics runs (null: none),
// and, if asked, each particle's displacement from the undeformed tissue.
Tissue present_tissue(const Tissue& tissue, const MechanicsSolver* mechanics,
                      std::vector<std::array<double, 2>>* displacement);

// What a snapshot shows, taken at time t: the run goes on while it is drawn.
struct SnapshotFrame {
  double t_ms = 0;
  std::shared_ptr<const Tissue> now;                // deformed, with mechanics; else the tissue itself
  std::vector<std::array<double, 2>> displacement;  // per particle, with mechanics and VTK
  std::vector<double> V_mV;
  CellStrainField strain;                           // per cell, with mechanics (else empty)
  double pixels_per_um = 0;                         // of the undeformed tissue
};
// `tissue` is the run's own (shared, not copied, when nothing moves it);
// `strain` the cells' strain now, with mechanics (null: none).
SnapshotFrame take_snapshot(double t, const SnapshotSpec& spec, const std::shared_ptr<const Tissue>& tissue,
                            const MechanicsSolver* mechanics, const std::vector<double>& V_mV,
                            const CellStrainField* strain = nullptr);

// The tissue coloured by membrane potential at the frame's time (the step's
// end): snapshot_<t>_ms.png and/or .vtk (.vtp, then added to
// snapshots.pvd) in dir, as spec asks; with the frame's strain, the VTK
// file's fields E_xx, E_yy, E_xy, fibre_stretch, max_shear and, with
// spec.strain, strain_<t>_ms.png (the deformed tissue coloured by E_yy).
void write_snapshot(const std::filesystem::path& dir, const SnapshotSpec& spec, const std::string& vtk_format,
                    const std::string& scene_name, const SnapshotFrame& frame);

// Per-cell maps of the last recorded beat: activation_map.png and maps.vtk (.vtp) in dir.
void write_maps(const std::filesystem::path& dir, const std::string& scene_name, const Tissue& tissue,
                const std::vector<BeatBiomarkers>& beats, const std::string& vtk_format);

}  // namespace fibrodem
