#include "io/vtk_writer.hpp"

#include <fstream>
#include <stdexcept>

namespace fibrodem {

void write_tissue_vtk(const Tissue& tissue, const std::filesystem::path& file,
                      const CellFields& fields, bool with_bonds,
                      const std::vector<std::array<double, 2>>* displacement_um) {
  for (const auto& [name, values] : fields)
    if (values.size() != tissue.cell_count())
      throw std::runtime_error("write_tissue_vtk: field '" + name + "' has " +
                               std::to_string(values.size()) + " values for " +
                               std::to_string(tissue.cell_count()) + " cells");
  std::ofstream out(file);
  if (!out) throw std::runtime_error("write_tissue_vtk: cannot write " + file.string());
  out.precision(9);
  const std::size_t n = tissue.particles.size();
  out << "# vtk DataFile Version 3.0\n"
      << "fibrodem tissue: " << tissue.cell_count() << " cells, " << n
      << " particles, lengths in um\nASCII\nDATASET POLYDATA\n";
  out << "POINTS " << n << " double\n";
  for (const Particle& p : tissue.particles) out << p.x_um << ' ' << p.y_um << " 0\n";
  out << "VERTICES " << n << ' ' << 2 * n << '\n';
  for (std::size_t i = 0; i < n; ++i) out << "1 " << i << '\n';
  if (with_bonds && !tissue.bonds.empty()) {
    out << "LINES " << tissue.bonds.size() << ' ' << 3 * tissue.bonds.size() << '\n';
    for (const Bond& b : tissue.bonds) out << "2 " << b.p << ' ' << b.q << '\n';
  }
  out << "POINT_DATA " << n << '\n';
  out << "SCALARS radius_um double 1\nLOOKUP_TABLE default\n";
  for (const Particle& p : tissue.particles) out << p.r_um << '\n';
  out << "SCALARS cell int 1\nLOOKUP_TABLE default\n";
  for (const Particle& p : tissue.particles) out << p.cell << '\n';
  out << "SCALARS cell_type int 1\nLOOKUP_TABLE default\n";
  for (const Particle& p : tissue.particles) out << static_cast<int>(tissue.type[p.cell]) << '\n';
  for (const auto& [name, values] : fields) {
    std::string clean = name.empty() ? std::string("field") : name;
    for (char& ch : clean)
      if (ch == ' ' || ch == '\t') ch = '_';
    out << "SCALARS " << clean << " double 1\nLOOKUP_TABLE default\n";
    for (const Particle& p : tissue.particles) out << values[p.cell] << '\n';
  }
  if (displacement_um) {
    if (displacement_um->size() != n) throw std::runtime_error("write_tissue_vtk: one displacement per particle");
    out << "VECTORS displacement_um double\n";
    for (const auto& d : *displacement_um) out << d[0] << ' ' << d[1] << " 0\n";
  }
  if (!out) throw std::runtime_error("write_tissue_vtk: error writing " + file.string());
}

}  // namespace fibrodem
