#include "io/vtk_xml_writer.hpp"

#include <zlib.h>

#include <algorithm>
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

#include "io/tissue_imprint.hpp"

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

// An array's XML element up to its offset.
template <class T>
std::string element_head(const std::string& name, int components) {
  return std::string("<DataArray type=\"") + vtk_type_name<T>() + "\" Name=\"" + name +
         "\" NumberOfComponents=\"" + std::to_string(components) + "\" format=\"appended\" offset=\"";
}

// Deflates one block of an array into `packed` (room for compressBound of
// a block); returns its compressed size.
std::size_t deflate_block(const unsigned char* raw, std::size_t bytes, std::vector<unsigned char>& packed,
                          const std::string& name) {
  uLongf packed_size = static_cast<uLongf>(packed.size());
  if (compress2(packed.data(), &packed_size, raw, static_cast<uLong>(bytes), kZlibLevel) != Z_OK)
    throw std::runtime_error("write_tissue_vtp: zlib failed to compress array '" + name + "'");
  return static_cast<std::size_t>(packed_size);
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
    a.element_head = element_head<T>(name, components);
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
  // An array packed before (VtpGeometryPacker), copied as it is.
  void add(const PackedVtpArray& packed) {
    Array a;
    a.element_head = packed.element_head;
    a.packed = &packed.appended;
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
    const std::vector<unsigned char>* packed = nullptr;  // its appended data as written, if packed before
  };

  // The header with these offsets, `padding` before the last text (the blanks
  // go between the closing tags and AppendedData).
  std::string header(const std::vector<std::uint64_t>& offsets, const std::string& padding) const {
    std::string xml;
    for (std::size_t i = 0; i < arrays_.size(); ++i)
      xml += texts_[i] + arrays_[i].element_head + std::to_string(offsets[i]) + "\"/>\n";
    return xml + texts_.back() + padding;
  }

  // One array's deflated blocks, each handed to put_block(data, bytes) in
  // turn; returns the block header (number of blocks, block size, size of
  // the last block if partial (else 0), compressed size of each block).
  static std::size_t block_count(const Array& a) { return (a.bytes + kBlockBytes - 1) / kBlockBytes; }

  template <class PutBlock>
  static std::vector<std::uint64_t> deflate_blocks(const Array& a, PutBlock&& put_block) {
    const std::size_t blocks = block_count(a);
    std::vector<std::uint64_t> block_header{blocks, kBlockBytes, a.bytes % kBlockBytes};
    block_header.resize(3 + blocks);
    std::vector<unsigned char> raw(kBlockBytes), packed(compressBound(kBlockBytes));
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::size_t begin = b * kBlockBytes, size = std::min(kBlockBytes, a.bytes - begin);
      a.fill(begin, size, raw.data());
      const std::size_t packed_size = deflate_block(raw.data(), size, packed, a.name);
      put_block(packed.data(), packed_size);
      block_header[3 + b] = packed_size;
    }
    return block_header;
  }

  // One array's appended data at `at`: the block header (UInt64 each) and
  // the deflated blocks. Returns its size.
  static std::uint64_t write_blocks(FILE* f, off_t at, const Array& a, const std::filesystem::path& file) {
    if (a.packed) {
      put(f, a.packed->data(), a.packed->size(), file);
      return a.packed->size();
    }
    const std::uint64_t header_bytes = 8 * (3 + block_count(a));
    seek(f, at + static_cast<off_t>(header_bytes), file);  // the header's room, written once the sizes are known
    std::uint64_t total = header_bytes;
    const std::vector<std::uint64_t> block_header = deflate_blocks(a, [&](const unsigned char* data, std::size_t n) {
      put(f, data, n, file);
      total += n;
    });
    seek(f, at, file);  // little-endian, the file's byte_order (checked in write_tissue_vtp)
    put(f, block_header.data(), header_bytes, file);
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

void check_input(std::size_t particles, const Tissue& tissue, const CellFields& fields,
                 const std::vector<std::array<double, 2>>* displacement_um) {
  for (const auto& [name, values] : fields)
    if (values.size() != tissue.cell_count())
      throw std::runtime_error("write_tissue_vtp: field '" + name + "' has " + std::to_string(values.size()) +
                               " values for " + std::to_string(tissue.cell_count()) + " cells");
  if (displacement_um && displacement_um->size() != particles)
    throw std::runtime_error("write_tissue_vtp: one displacement per particle");
  if (particles + 1 > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()) ||
      2 * tissue.bonds.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw std::runtime_error("write_tissue_vtp: " + std::to_string(particles) + " particles, more than Int32 indexes");
}

std::string point_data_head(const CellFields& fields, bool with_displacement) {
  return "<PointData Scalars=\"" + (fields.empty() ? std::string("cell_type") : clean_name(fields.front().first)) +
         "\"" + (with_displacement ? " Vectors=\"displacement_um\"" : "") + ">\n";
}

// (The arrays' values are taken as the file is written: the lambdas hold
// pointers into the tissue and fields, which outlive the writing.)
void add_particle_arrays(AppendedArrays& arrays, const Tissue& tissue) {
  const std::size_t n = tissue.particles.size();
  const Particle* particles = tissue.particles.data();
  const CellType* type = tissue.type.data();
  arrays.add<float>("radius_um", 1, n, [particles](std::size_t i) { return static_cast<float>(particles[i].r_um); });
  arrays.add<std::int32_t>("cell", 1, n,
                           [particles](std::size_t i) { return static_cast<std::int32_t>(particles[i].cell); });
  arrays.add<std::uint8_t>("cell_type", 1, n, [particles, type](std::size_t i) {
    return static_cast<std::uint8_t>(type[particles[i].cell]);
  });
}

void add_points(AppendedArrays& arrays, const Tissue& tissue) {
  const Particle* particles = tissue.particles.data();
  arrays.add<float>("Points", 3, 3 * tissue.particles.size(), [particles](std::size_t i) {
    const Particle& p = particles[i / 3];
    return i % 3 == 0 ? static_cast<float>(p.x_um) : i % 3 == 1 ? static_cast<float>(p.y_um) : 0.0f;
  });
}

// One vertex per particle: connectivity i, offsets (each cell's end) i + 1.
void add_vertices(AppendedArrays& arrays, std::size_t n) {
  arrays.add<std::int32_t>("connectivity", 1, n, [](std::size_t i) { return static_cast<std::int32_t>(i); });
  arrays.add<std::int32_t>("offsets", 1, n, [](std::size_t i) { return static_cast<std::int32_t>(i + 1); });
}

// A particle's cell read from an imprint's runs: particles are asked for in
// order (block by block), so the run is found once and then followed.
class CellOfParticle {
 public:
  explicit CellOfParticle(const ParticleCellRuns& runs) : runs_(runs) {}
  std::int32_t operator()(std::size_t p) const {
    const auto& end = runs_.end;
    if (k_ >= end.size() || (k_ > 0 && p < static_cast<std::size_t>(end[k_ - 1])))
      k_ = static_cast<std::size_t>(std::upper_bound(end.begin(), end.end(), static_cast<std::int32_t>(p)) -
                                    end.begin());
    while (p >= static_cast<std::size_t>(end[k_])) ++k_;
    return runs_.cell[k_];
  }

 private:
  const ParticleCellRuns& runs_;
  mutable std::size_t k_ = 0;
};

void add_fields(AppendedArrays& arrays, const CellFields& fields, std::size_t n, const auto& cell_of) {
  for (const auto& field : fields) {
    const double* values = field.second.data();
    arrays.add<float>(clean_name(field.first), 1, n,
                      [&cell_of, values](std::size_t i) { return static_cast<float>(values[cell_of(i)]); });
  }
}

void add_displacement(AppendedArrays& arrays, const std::vector<std::array<double, 2>>& displacement_um) {
  const std::array<double, 2>* d = displacement_um.data();
  arrays.add<float>("displacement_um", 3, 3 * displacement_um.size(),
                    [d](std::size_t i) { return i % 3 == 2 ? 0.0f : static_cast<float>(d[i / 3][i % 3]); });
}

void add_bonds(AppendedArrays& arrays, const std::vector<Bond>& tissue_bonds) {
  const Bond* bonds = tissue_bonds.data();
  arrays.text("<Lines>\n");
  arrays.add<std::int32_t>("connectivity", 1, 2 * tissue_bonds.size(),
                           [bonds](std::size_t i) { return i % 2 == 0 ? bonds[i / 2].p : bonds[i / 2].q; });
  arrays.add<std::int32_t>("offsets", 1, tissue_bonds.size(),
                           [](std::size_t b) { return static_cast<std::int32_t>(2 * b + 2); });
  arrays.text("</Lines>\n");
}

std::string file_head(std::size_t particles, std::size_t lines) {
  const std::string n = std::to_string(particles);
  return "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" "
         "compressor=\"vtkZLibDataCompressor\">\n<PolyData>\n"
         "<Piece NumberOfPoints=\"" + n + "\" NumberOfVerts=\"" + n + "\" NumberOfLines=\"" +
         std::to_string(lines) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
}

void write_arrays(AppendedArrays& arrays, const std::filesystem::path& file) {
  arrays.text("</Piece>\n</PolyData>\n");
  arrays.write(file, "<AppendedData encoding=\"raw\">\n_", "\n</AppendedData>\n</VTKFile>\n");
}

// A tissue whose particles were released, from its imprint: the arrays in
// the order write_tissue_vtp writes them.
void write_from_imprint(const Tissue& tissue, const TissueImprint& imprint, const std::filesystem::path& file,
                        const CellFields& fields, bool with_bonds,
                        const std::vector<std::array<double, 2>>* displacement_um) {
  if (with_bonds || displacement_um)
    throw std::logic_error("write_tissue_vtp: " + file.string() + ": the tissue's particles were released with an "
                           "imprint, which holds neither bonds nor displacements");
  const std::size_t n = imprint.cells.particles();
  check_input(n, tissue, fields, nullptr);
  AppendedArrays arrays;
  arrays.text(file_head(n, 0));
  arrays.text(point_data_head(fields, false));
  for (const PackedVtpArray* a : {&imprint.vtp.radius, &imprint.vtp.cell, &imprint.vtp.cell_type}) arrays.add(*a);
  const CellOfParticle cell_of(imprint.cells);
  add_fields(arrays, fields, n, cell_of);
  arrays.text("</PointData>\n<CellData/>\n<Points>\n");
  arrays.add(imprint.vtp.points);
  arrays.text("</Points>\n<Verts>\n");
  add_vertices(arrays, n);
  arrays.text("</Verts>\n");
  write_arrays(arrays, file);
}

}  // namespace

void write_tissue_vtp(const Tissue& tissue, const std::filesystem::path& file, const CellFields& fields,
                      bool with_bonds, const std::vector<std::array<double, 2>>* displacement_um) {
  static_assert(std::endian::native == std::endian::little, "the file says byte_order LittleEndian");
  if (tissue.particles.empty() && tissue.imprint())
    return write_from_imprint(tissue, *tissue.imprint(), file, fields, with_bonds, displacement_um);
  const std::size_t n = tissue.particles.size();
  check_input(n, tissue, fields, displacement_um);
  const bool lines = with_bonds && !tissue.bonds.empty();
  AppendedArrays arrays;
  arrays.text(file_head(n, lines ? tissue.bonds.size() : 0));
  arrays.text(point_data_head(fields, displacement_um != nullptr));
  add_particle_arrays(arrays, tissue);
  const Particle* particles = tissue.particles.data();
  const auto cell_of = [particles](std::size_t i) { return particles[i].cell; };
  add_fields(arrays, fields, n, cell_of);
  if (displacement_um) add_displacement(arrays, *displacement_um);
  arrays.text("</PointData>\n<CellData/>\n<Points>\n");
  add_points(arrays, tissue);
  arrays.text("</Points>\n<Verts>\n");
  add_vertices(arrays, n);
  arrays.text("</Verts>\n");
  if (lines) add_bonds(arrays, tissue.bonds);
  write_arrays(arrays, file);
}

// One array packed as its values come: each full block deflated at once,
// the appended data (block header, blocks) made at the end, as
// AppendedArrays writes an array.
class VtpGeometryPacker::ArrayPacker {
 public:
  ArrayPacker(std::string name, std::string element_head)
      : name_(std::move(name)), packed_{std::move(element_head), {}} {
    raw_.reserve(kBlockBytes);
  }
  template <class T>
  void add(T value) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(&value);
    raw_.insert(raw_.end(), bytes, bytes + sizeof(T));  // (a block holds whole values: 2^16 bytes)
    if (raw_.size() == kBlockBytes) deflate_raw();
  }
  PackedVtpArray finish() {
    const std::size_t last = raw_.size();
    if (last > 0) deflate_raw();
    std::vector<std::uint64_t> header{block_sizes_.size(), kBlockBytes, last};
    header.insert(header.end(), block_sizes_.begin(), block_sizes_.end());
    std::vector<unsigned char>& out = packed_.appended;
    out.reserve(8 * header.size() + blocks_.size());
    out.resize(8 * header.size());
    std::memcpy(out.data(), header.data(), out.size());  // little-endian, the file's byte_order
    out.insert(out.end(), blocks_.begin(), blocks_.end());
    std::vector<unsigned char>().swap(blocks_);
    return std::move(packed_);
  }

 private:
  void deflate_raw() {
    const std::size_t n = deflate_block(raw_.data(), raw_.size(), deflated_, name_);
    blocks_.insert(blocks_.end(), deflated_.begin(), deflated_.begin() + static_cast<std::ptrdiff_t>(n));
    block_sizes_.push_back(n);
    raw_.clear();
  }

  std::string name_;
  PackedVtpArray packed_;
  std::vector<unsigned char> raw_, blocks_, deflated_ = std::vector<unsigned char>(compressBound(kBlockBytes));
  std::vector<std::uint64_t> block_sizes_;
};

// The arrays add_particle_arrays and add_points write.
VtpGeometryPacker::VtpGeometryPacker()
    : radius_(std::make_unique<ArrayPacker>("radius_um", element_head<float>("radius_um", 1))),
      cell_(std::make_unique<ArrayPacker>("cell", element_head<std::int32_t>("cell", 1))),
      cell_type_(std::make_unique<ArrayPacker>("cell_type", element_head<std::uint8_t>("cell_type", 1))),
      points_(std::make_unique<ArrayPacker>("Points", element_head<float>("Points", 3))) {}

VtpGeometryPacker::~VtpGeometryPacker() = default;

void VtpGeometryPacker::add(const Particle& p, CellType type) {
  radius_->add(static_cast<float>(p.r_um));
  cell_->add(static_cast<std::int32_t>(p.cell));
  cell_type_->add(static_cast<std::uint8_t>(type));
  points_->add(static_cast<float>(p.x_um));
  points_->add(static_cast<float>(p.y_um));
  points_->add(0.0f);
}

PackedVtpGeometry VtpGeometryPacker::finish() {
  return {radius_->finish(), cell_->finish(), cell_type_->finish(), points_->finish()};
}

std::size_t PackedVtpGeometry::bytes() const {
  std::size_t total = 0;
  for (const PackedVtpArray* a : {&radius, &cell, &cell_type, &points})
    total += a->appended.size() + a->element_head.size();
  return total;
}

}  // namespace fibrodem
