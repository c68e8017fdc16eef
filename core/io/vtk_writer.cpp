#include "io/vtk_writer.hpp"

#include <charconv>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <type_traits>

namespace fibrodem {

namespace {

// The file's text, formatted with std::to_chars into a buffer that goes to
// the file whenever it holds kFlushBytes (a snapshot of the Fig. 3 tissue is
// ~17k particles x 8 numbers, which an ostream formats at a few times the
// cost; and the text of a 1e6-cell tissue, ~0.4 GB, is never held whole).
// Doubles are written as printf's %.9g.
class VtkText {
 public:
  explicit VtkText(const std::filesystem::path& file) : file_(file), f_(std::fopen(file.c_str(), "wb"), &std::fclose) {
    if (!f_) throw std::runtime_error("write_tissue_vtk: cannot write " + file.string());
    text_.reserve(kFlushBytes + 256);
  }
  VtkText& operator<<(const std::string& s) { return text_.append(s), spill(); }
  VtkText& operator<<(const char* s) { return text_.append(s), spill(); }
  VtkText& operator<<(char c) { return text_.push_back(c), spill(); }
  template <class T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
  VtkText& operator<<(T value) {
    char digits[32];
    std::to_chars_result r;
    if constexpr (std::is_floating_point_v<T>)
      r = std::to_chars(digits, digits + sizeof digits, static_cast<double>(value), std::chars_format::general, 9);
    else
      r = std::to_chars(digits, digits + sizeof digits, value);
    text_.append(digits, r.ptr);
    return spill();
  }
  // Writes what is left and closes the file.
  void close() {
    flush();
    if (std::fclose(f_.release()) != 0) throw std::runtime_error("write_tissue_vtk: error writing " + file_.string());
  }

 private:
  static constexpr std::size_t kFlushBytes = 1 << 16;
  VtkText& spill() {
    if (text_.size() >= kFlushBytes) flush();
    return *this;
  }
  void flush() {
    if (std::fwrite(text_.data(), 1, text_.size(), f_.get()) != text_.size())
      throw std::runtime_error("write_tissue_vtk: error writing " + file_.string());
    text_.clear();
  }
  std::filesystem::path file_;
  std::unique_ptr<FILE, decltype(&std::fclose)> f_;
  std::string text_;
};

}  // namespace

void write_tissue_vtk(const Tissue& tissue, const std::filesystem::path& file,
                      const CellFields& fields, bool with_bonds,
                      const std::vector<std::array<double, 2>>* displacement_um) {
  for (const auto& [name, values] : fields)
    if (values.size() != tissue.cell_count())
      throw std::runtime_error("write_tissue_vtk: field '" + name + "' has " +
                               std::to_string(values.size()) + " values for " +
                               std::to_string(tissue.cell_count()) + " cells");
  const std::size_t n = tissue.particles.size();
  if (displacement_um && displacement_um->size() != n)
    throw std::runtime_error("write_tissue_vtk: one displacement per particle");
  VtkText out(file);
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
    out << "VECTORS displacement_um double\n";
    for (const auto& d : *displacement_um) out << d[0] << ' ' << d[1] << " 0\n";
  }
  out.close();
}

}  // namespace fibrodem
