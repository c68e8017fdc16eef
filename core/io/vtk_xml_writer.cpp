#include "io/vtk_xml_writer.hpp"

#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <bit>
#include <cstring>
#include <functional>
#include <sys/types.h>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace fibrodem {

namespace {

// Uncompressed bytes per block: each block is deflated on its own (the VTK
// XML format), so a reader can inflate them one by one.
constexpr std::size_t kBlockBytes = 1 << 16;
// zlib's fastest level, as for the PNG pictures: on a 1e6-cell snapshot of
// V the default level (6) saves 1 % of the size for 7 times the time
// (docs/topics/performance.md).
constexpr int kZlibLevel = Z_BEST_SPEED;

template <class T>
constexpr const char* vtk_type_name() {
  if constexpr (std::is_same_v<T, float>) return "Float32";
  else if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
  else if constexpr (std::is_same_v<T, std::uint8_t>) return "UInt8";
  else static_assert(sizeof(T) == 0, "no VTK type for T");
}

// Writes to the file, or throws naming it.
void put(FILE* f, const void* data, std::size_t bytes, const std::filesystem::path& file) {
  if (bytes > 0 && std::fwrite(data, 1, bytes, f) != bytes)
    throw std::runtime_error("write_tissue_vtp: error writing " + file.string());
}

void seek(FILE* f, off_t at, const std::filesystem::path& file) {
  if (fseeko(f, at, SEEK_SET) != 0) throw std::runtime_error("write_tissue_vtp: cannot seek in " + file.string());
}

// The file's arrays: the XML header's DataArray elements, and the appended
// data streamed to the file block by block, so that neither the arrays nor
// their compressed bytes are ever held whole (a 1e6-cell tissue's would be
// ~0.2 GB). The offsets in the header are known once the data is written:
// the header's room is reserved with the widest offsets, and the header
// written last, padded with blanks between elements to fill its room.
class AppendedArrays {
 public:
  // Text of the header between the last array's element (or the start) and the next.
  void text(const std::string& xml) { texts_.back() += xml; }
  // An array of `count` values of T (components per tuple), value_at(i) the
  // i-th in the file's order.
  template <class T, class ValueAt>
  void add(const std::string& name, int components, std::size_t count, ValueAt value_at) {
    Array a;
    a.element_head = std::string("<DataArray type=\"") + vtk_type_name<T>() + "\" Name=\"" + name +
                     "\" NumberOfComponents=\"" + std::to_string(components) + "\" format=\"appended\" offset=\"";
    a.name = name;
    a.bytes = count * sizeof(T);
    a.fill = [value_at](std::size_t first_byte, std::size_t bytes, unsigned char* out) {
      T* values = reinterpret_cast<T*>(out);
      const std::size_t first = first_byte / sizeof(T), n = bytes / sizeof(T);
      for (std::size_t i = 0; i < n; ++i) values[i] = value_at(first + i);
    };
    arrays_.push_back(std::move(a));
    texts_.emplace_back();
  }
  // Writes the whole file: the header, "_", the appended data, `tail`.
  void write(const std::filesystem::path& file, const std::string& appended_tag, const std::string& tail) {
    std::unique_ptr<FILE, decltype(&std::fclose)> f(std::fopen(file.c_str(), "wb"), &std::fclose);
    if (!f) throw std::runtime_error("write_tissue_vtp: cannot write " + file.string());
    const std::size_t room = header(std::vector<std::uint64_t>(arrays_.size(), kWidestOffset), "").size() +
                             appended_tag.size();
    seek(f.get(), static_cast<off_t>(room), file);
    std::vector<std::uint64_t> offsets;
    std::uint64_t at = 0;
    for (const Array& a : arrays_) {
      offsets.push_back(at);
      at += write_blocks(f.get(), static_cast<off_t>(room + at), a, file);
    }
    put(f.get(), tail.data(), tail.size(), file);
    std::string head = header(offsets, "");
    head = header(offsets, std::string(room - head.size() - appended_tag.size(), ' ')) + appended_tag;
    seek(f.get(), 0, file);
    put(f.get(), head.data(), head.size(), file);
    if (std::fclose(f.release()) != 0) throw std::runtime_error("write_tissue_vtp: error writing " + file.string());
  }

 private:
  static constexpr std::uint64_t kWidestOffset = std::numeric_limits<std::uint64_t>::max();
  struct Array {
    std::string element_head, name;
    std::size_t bytes = 0;
    std::function<void(std::size_t first_byte, std::size_t bytes, unsigned char* out)> fill;
  };

  // The header with these offsets, `padding` before the last text (the blanks
  // go between the closing tags and AppendedData).
  std::string header(const std::vector<std::uint64_t>& offsets, const std::string& padding) const {
    std::string xml;
    for (std::size_t i = 0; i < arrays_.size(); ++i)
      xml += texts_[i] + arrays_[i].element_head + std::to_string(offsets[i]) + "\"/>\n";
    return xml + texts_.back() + padding;
  }

  // One array's appended data at `at`: the block header (number of blocks,
  // block size, size of the last block if partial (else 0), compressed size
  // of each block, as UInt64) and the deflated blocks. Returns its size.
  static std::uint64_t write_blocks(FILE* f, off_t at, const Array& a, const std::filesystem::path& file) {
    const std::size_t blocks = (a.bytes + kBlockBytes - 1) / kBlockBytes;
    std::vector<std::uint64_t> block_header{blocks, kBlockBytes, a.bytes % kBlockBytes};
    block_header.resize(3 + blocks);  // compressed sizes: filled in below
    put(f, block_header.data(), 8 * block_header.size(), file);
    std::vector<unsigned char> raw(kBlockBytes), packed(compressBound(kBlockBytes));
    std::uint64_t total = 8 * block_header.size();
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::size_t begin = b * kBlockBytes, size = std::min(kBlockBytes, a.bytes - begin);
      a.fill(begin, size, raw.data());
      uLongf packed_size = static_cast<uLongf>(packed.size());
      if (compress2(packed.data(), &packed_size, raw.data(), static_cast<uLong>(size), kZlibLevel) != Z_OK)
        throw std::runtime_error("write_tissue_vtp: zlib failed to compress array '" + a.name + "'");
      put(f, packed.data(), packed_size, file);
      block_header[3 + b] = packed_size;
      total += packed_size;
    }
    seek(f, at, file);  // little-endian, the file's byte_order (checked in write_tissue_vtp)
    put(f, block_header.data(), 8 * block_header.size(), file);
    seek(f, at + static_cast<off_t>(total), file);
    return total;
  }

  std::vector<std::string> texts_{1};  // texts_[i] before array i; the last after them all
  std::vector<Array> arrays_;
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

// (The arrays' values are taken as the file is written: the lambdas hold
// pointers into the tissue and fields, which outlive the writing.)
void add_point_data(AppendedArrays& arrays, const Tissue& tissue, const CellFields& fields,
                    const std::vector<std::array<double, 2>>* displacement_um) {
  const std::size_t n = tissue.particles.size();
  const Particle* particles = tissue.particles.data();
  const CellType* type = tissue.type.data();
  arrays.text("<PointData Scalars=\"" + (fields.empty() ? std::string("cell_type") : clean_name(fields.front().first)) +
              "\"" + (displacement_um ? " Vectors=\"displacement_um\"" : "") + ">\n");
  arrays.add<float>("radius_um", 1, n, [particles](std::size_t i) { return static_cast<float>(particles[i].r_um); });
  arrays.add<std::int32_t>("cell", 1, n,
                           [particles](std::size_t i) { return static_cast<std::int32_t>(particles[i].cell); });
  arrays.add<std::uint8_t>("cell_type", 1, n, [particles, type](std::size_t i) {
    return static_cast<std::uint8_t>(type[particles[i].cell]);
  });
  for (const auto& field : fields) {
    const double* values = field.second.data();
    arrays.add<float>(clean_name(field.first), 1, n, [particles, values](std::size_t i) {
      return static_cast<float>(values[particles[i].cell]);
    });
  }
  if (displacement_um) {
    const std::array<double, 2>* d = displacement_um->data();
    arrays.add<float>("displacement_um", 3, 3 * n,
                      [d](std::size_t i) { return i % 3 == 2 ? 0.0f : static_cast<float>(d[i / 3][i % 3]); });
  }
  arrays.text("</PointData>\n<CellData/>\n");
}

void add_geometry(AppendedArrays& arrays, const Tissue& tissue, bool with_bonds) {
  const std::size_t n = tissue.particles.size();
  const Particle* particles = tissue.particles.data();
  arrays.text("<Points>\n");
  arrays.add<float>("Points", 3, 3 * n, [particles](std::size_t i) {
    const Particle& p = particles[i / 3];
    return i % 3 == 0 ? static_cast<float>(p.x_um) : i % 3 == 1 ? static_cast<float>(p.y_um) : 0.0f;
  });
  arrays.text("</Points>\n<Verts>\n");
  // One vertex per particle: connectivity i, offsets (each cell's end) i + 1.
  arrays.add<std::int32_t>("connectivity", 1, n, [](std::size_t i) { return static_cast<std::int32_t>(i); });
  arrays.add<std::int32_t>("offsets", 1, n, [](std::size_t i) { return static_cast<std::int32_t>(i + 1); });
  arrays.text("</Verts>\n");
  if (with_bonds && !tissue.bonds.empty()) {
    const Bond* bonds = tissue.bonds.data();
    arrays.text("<Lines>\n");
    arrays.add<std::int32_t>("connectivity", 1, 2 * tissue.bonds.size(),
                             [bonds](std::size_t i) { return i % 2 == 0 ? bonds[i / 2].p : bonds[i / 2].q; });
    arrays.add<std::int32_t>("offsets", 1, tissue.bonds.size(),
                             [](std::size_t b) { return static_cast<std::int32_t>(2 * b + 2); });
    arrays.text("</Lines>\n");
  }
}

}  // namespace

void write_tissue_vtp(const Tissue& tissue, const std::filesystem::path& file, const CellFields& fields,
                      bool with_bonds, const std::vector<std::array<double, 2>>* displacement_um) {
  static_assert(std::endian::native == std::endian::little, "the file says byte_order LittleEndian");
  check_input(tissue, fields, displacement_um);
  const std::size_t n = tissue.particles.size();
  const std::size_t lines = with_bonds ? tissue.bonds.size() : 0;
  AppendedArrays arrays;
  arrays.text(
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" "
      "compressor=\"vtkZLibDataCompressor\">\n<PolyData>\n");
  arrays.text("<Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"" + std::to_string(n) +
              "\" NumberOfLines=\"" + std::to_string(lines) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n");
  add_point_data(arrays, tissue, fields, displacement_um);
  add_geometry(arrays, tissue, with_bonds);
  arrays.text("</Piece>\n</PolyData>\n");
  arrays.write(file, "<AppendedData encoding=\"raw\">\n_", "\n</AppendedData>\n</VTKFile>\n");
}

}  // namespace fibrodem
