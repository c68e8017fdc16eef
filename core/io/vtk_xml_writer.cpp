#include "io/vtk_xml_writer.hpp"

#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <bit>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace fibrodem {

namespace {

// Uncompressed bytes per block: each block is deflated on its own (the VTK
// XML format), so a reader can inflate them one by one.
constexpr std::size_t kBlockBytes = 1 << 16;
// zlib's fastest level, as for the PNG pictures: on a 1e6-cell snapshot of
// V the default level (6) saves 1 % of the size for 7 times the time
// (docs/performance.md).
constexpr int kZlibLevel = Z_BEST_SPEED;

template <class T>
constexpr const char* vtk_type_name() {
  if constexpr (std::is_same_v<T, float>) return "Float32";
  else if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
  else if constexpr (std::is_same_v<T, std::uint8_t>) return "UInt8";
  else static_assert(sizeof(T) == 0, "no VTK type for T");
}

void put_u64(std::string& out, std::uint64_t v) {
  char bytes[8];
  std::memcpy(bytes, &v, 8);  // little-endian (the file's byte_order; checked below)
  out.append(bytes, 8);
}

// One array's appended data: the block header (number of blocks, block
// size, size of the last block if partial (else 0), compressed size of each
// block, as UInt64) and the deflated blocks.
std::string compress_blocks(const unsigned char* data, std::size_t bytes, const std::string& array_name) {
  const std::size_t blocks = (bytes + kBlockBytes - 1) / kBlockBytes;
  std::string packed;
  std::vector<std::uint64_t> packed_sizes;
  std::vector<unsigned char> buffer(compressBound(kBlockBytes));
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t begin = b * kBlockBytes, size = std::min(kBlockBytes, bytes - begin);
    uLongf packed_size = static_cast<uLongf>(buffer.size());
    if (compress2(buffer.data(), &packed_size, data + begin, static_cast<uLong>(size), kZlibLevel) != Z_OK)
      throw std::runtime_error("write_tissue_vtp: zlib failed to compress array '" + array_name + "'");
    packed.append(reinterpret_cast<const char*>(buffer.data()), packed_size);
    packed_sizes.push_back(packed_size);
  }
  std::string out;
  put_u64(out, blocks);
  put_u64(out, kBlockBytes);
  put_u64(out, bytes % kBlockBytes);
  for (const auto s : packed_sizes) put_u64(out, s);
  return out + packed;
}

// The XML header's array elements and the appended data they point into.
class AppendedArrays {
 public:
  template <class T>
  void add(std::string& xml, const std::string& name, int components, const std::vector<T>& values) {
    xml += std::string("<DataArray type=\"") + vtk_type_name<T>() + "\" Name=\"" + name +
           "\" NumberOfComponents=\"" + std::to_string(components) + "\" format=\"appended\" offset=\"" +
           std::to_string(data_.size()) + "\"/>\n";
    data_ += compress_blocks(reinterpret_cast<const unsigned char*>(values.data()), values.size() * sizeof(T), name);
  }
  const std::string& data() const { return data_; }

 private:
  std::string data_;
};

std::string clean_name(const std::string& name) {
  std::string clean = name.empty() ? std::string("field") : name;
  for (char& ch : clean)
    if (ch == ' ' || ch == '\t') ch = '_';
  // The name goes into an XML attribute.
  std::string escaped;
  for (char ch : clean) {
    if (ch == '&') escaped += "&amp;";
    else if (ch == '<') escaped += "&lt;";
    else if (ch == '>') escaped += "&gt;";
    else if (ch == '"') escaped += "&quot;";
    else escaped += ch;
  }
  return escaped;
}

void check_input(const Tissue& tissue, const CellFields& fields,
                 const std::vector<std::array<double, 2>>* displacement_um) {
  for (const auto& [name, values] : fields)
    if (values.size() != tissue.cell_count())
      throw std::runtime_error("write_tissue_vtp: field '" + name + "' has " + std::to_string(values.size()) +
                               " values for " + std::to_string(tissue.cell_count()) + " cells");
  if (displacement_um && displacement_um->size() != tissue.particles.size())
    throw std::runtime_error("write_tissue_vtp: one displacement per particle");
  if (tissue.particles.size() + 1 > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()) ||
      2 * tissue.bonds.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw std::runtime_error("write_tissue_vtp: " + std::to_string(tissue.particles.size()) +
                             " particles, more than Int32 indexes");
}

void write_point_data(std::string& xml, AppendedArrays& arrays, const Tissue& tissue, const CellFields& fields,
                      const std::vector<std::array<double, 2>>* displacement_um) {
  const std::size_t n = tissue.particles.size();
  xml += "<PointData Scalars=\"" + (fields.empty() ? std::string("cell_type") : clean_name(fields.front().first)) +
         "\"" + (displacement_um ? " Vectors=\"displacement_um\"" : "") + ">\n";
  std::vector<float> radius(n);
  std::vector<std::int32_t> cell(n);
  std::vector<std::uint8_t> type(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Particle& p = tissue.particles[i];
    radius[i] = static_cast<float>(p.r_um);
    cell[i] = p.cell;
    type[i] = static_cast<std::uint8_t>(tissue.type[p.cell]);
  }
  arrays.add(xml, "radius_um", 1, radius);
  arrays.add(xml, "cell", 1, cell);
  arrays.add(xml, "cell_type", 1, type);
  std::vector<float> field(n);
  for (const auto& [name, values] : fields) {
    for (std::size_t i = 0; i < n; ++i) field[i] = static_cast<float>(values[tissue.particles[i].cell]);
    arrays.add(xml, clean_name(name), 1, field);
  }
  if (displacement_um) {
    std::vector<float> d(3 * n, 0.0f);
    for (std::size_t i = 0; i < n; ++i) {
      d[3 * i] = static_cast<float>((*displacement_um)[i][0]);
      d[3 * i + 1] = static_cast<float>((*displacement_um)[i][1]);
    }
    arrays.add(xml, "displacement_um", 3, d);
  }
  xml += "</PointData>\n<CellData/>\n";
}

void write_geometry(std::string& xml, AppendedArrays& arrays, const Tissue& tissue, bool with_bonds) {
  const std::size_t n = tissue.particles.size();
  std::vector<float> points(3 * n, 0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    points[3 * i] = static_cast<float>(tissue.particles[i].x_um);
    points[3 * i + 1] = static_cast<float>(tissue.particles[i].y_um);
  }
  xml += "<Points>\n";
  arrays.add(xml, "Points", 3, points);
  xml += "</Points>\n<Verts>\n";
  // One vertex per particle: connectivity i, offsets (each cell's end) i + 1.
  std::vector<std::int32_t> connectivity(n), offsets(n);
  for (std::size_t i = 0; i < n; ++i) {
    connectivity[i] = static_cast<std::int32_t>(i);
    offsets[i] = static_cast<std::int32_t>(i + 1);
  }
  arrays.add(xml, "connectivity", 1, connectivity);
  arrays.add(xml, "offsets", 1, offsets);
  xml += "</Verts>\n";
  if (with_bonds && !tissue.bonds.empty()) {
    const std::size_t m = tissue.bonds.size();
    std::vector<std::int32_t> ends(2 * m), line_offsets(m);
    for (std::size_t b = 0; b < m; ++b) {
      ends[2 * b] = tissue.bonds[b].p;
      ends[2 * b + 1] = tissue.bonds[b].q;
      line_offsets[b] = static_cast<std::int32_t>(2 * b + 2);
    }
    xml += "<Lines>\n";
    arrays.add(xml, "connectivity", 1, ends);
    arrays.add(xml, "offsets", 1, line_offsets);
    xml += "</Lines>\n";
  }
}

}  // namespace

void write_tissue_vtp(const Tissue& tissue, const std::filesystem::path& file, const CellFields& fields,
                      bool with_bonds, const std::vector<std::array<double, 2>>* displacement_um) {
  static_assert(std::endian::native == std::endian::little, "the file says byte_order LittleEndian");
  check_input(tissue, fields, displacement_um);
  const std::size_t n = tissue.particles.size();
  const std::size_t lines = with_bonds ? tissue.bonds.size() : 0;
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" "
      "compressor=\"vtkZLibDataCompressor\">\n<PolyData>\n";
  xml += "<Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"" + std::to_string(n) +
         "\" NumberOfLines=\"" + std::to_string(lines) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
  AppendedArrays arrays;
  write_point_data(xml, arrays, tissue, fields, displacement_um);
  write_geometry(xml, arrays, tissue, with_bonds);
  xml += "</Piece>\n</PolyData>\n<AppendedData encoding=\"raw\">\n_";

  std::unique_ptr<FILE, decltype(&std::fclose)> f(std::fopen(file.c_str(), "wb"), &std::fclose);
  if (!f) throw std::runtime_error("write_tissue_vtp: cannot write " + file.string());
  const std::string tail = "\n</AppendedData>\n</VTKFile>\n";
  const std::string& data = arrays.data();
  if (std::fwrite(xml.data(), 1, xml.size(), f.get()) != xml.size() ||
      std::fwrite(data.data(), 1, data.size(), f.get()) != data.size() ||
      std::fwrite(tail.data(), 1, tail.size(), f.get()) != tail.size() || std::fclose(f.release()) != 0)
    throw std::runtime_error("write_tissue_vtp: error writing " + file.string());
}

}  // namespace fibrodem
