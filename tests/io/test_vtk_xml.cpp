// VTK XML PolyData (.vtp) files and their time collection (.pvd): read back
// here with an independent reader (pugixml for the header, zlib for the
// appended blocks, as the VTK XML file format describes them) and compared
// with the tissue written and with the legacy ASCII file of the same tissue.
#include <doctest/doctest.h>
#include <zlib.h>

#include <pugixml.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <sstream>

#include "io/pvd_collection.hpp"
#include "io/vtk_writer.hpp"
#include "io/vtk_xml_writer.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

// A .vtp file's header (as XML) and its arrays, decompressed.
struct VtpFile {
  pugi::xml_document header;
  std::map<std::string, std::string> bytes;  // "PointData/V_mV", "Points/Points", "Verts/offsets", ...
  std::map<std::string, std::string> types;

  template <class T>
  std::vector<T> array(const std::string& key) const {
    const std::string& b = bytes.at(key);
    REQUIRE(b.size() % sizeof(T) == 0);
    std::vector<T> values(b.size() / sizeof(T));
    std::memcpy(values.data(), b.data(), b.size());
    return values;
  }
};

std::uint64_t u64_at(const std::string& s, std::size_t at) {
  REQUIRE(at + 8 <= s.size());
  std::uint64_t v;
  std::memcpy(&v, s.data() + at, 8);
  return v;
}

// One array's appended data at `offset` (after the '_'): header
// [blocks][block size][last partial block size or 0][compressed sizes...], then the blocks.
std::string inflate_array(const std::string& appended, std::size_t offset) {
  const std::uint64_t blocks = u64_at(appended, offset), block = u64_at(appended, offset + 8),
                      last = u64_at(appended, offset + 16);
  std::size_t at = offset + 24 + 8 * blocks;
  std::string out;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t packed = u64_at(appended, offset + 24 + 8 * b);
    const std::uint64_t expected = (b + 1 == blocks && last != 0) ? last : block;
    std::string raw(expected, '\0');
    uLongf raw_size = static_cast<uLongf>(expected);
    REQUIRE(at + packed <= appended.size());
    REQUIRE(uncompress(reinterpret_cast<Bytef*>(raw.data()), &raw_size,
                       reinterpret_cast<const Bytef*>(appended.data() + at), static_cast<uLong>(packed)) == Z_OK);
    REQUIRE(raw_size == expected);
    out += raw;
    at += packed;
  }
  return out;
}

VtpFile read_vtp(const std::filesystem::path& file) {
  const std::string text = testing::read_file(file);
  const std::size_t appended_tag = text.find("<AppendedData encoding=\"raw\">");
  REQUIRE(appended_tag != std::string::npos);
  const std::size_t underscore = text.find('_', appended_tag);
  REQUIRE(underscore != std::string::npos);
  const std::string appended = text.substr(underscore + 1);
  CHECK(appended.ends_with("\n</AppendedData>\n</VTKFile>\n"));
  VtpFile vtp;
  // The header is well-formed XML once the appended part is cut and VTKFile closed.
  REQUIRE(vtp.header.load_string((text.substr(0, appended_tag) + "</VTKFile>").c_str()));
  const pugi::xml_node root = vtp.header.child("VTKFile");
  CHECK(std::string(root.attribute("type").value()) == "PolyData");
  CHECK(std::string(root.attribute("byte_order").value()) == "LittleEndian");
  CHECK(std::string(root.attribute("header_type").value()) == "UInt64");
  CHECK(std::string(root.attribute("compressor").value()) == "vtkZLibDataCompressor");
  for (const pugi::xml_node part : root.child("PolyData").child("Piece").children())
    for (const pugi::xml_node a : part.children("DataArray")) {
      CHECK(std::string(a.attribute("format").value()) == "appended");
      const std::string key = std::string(part.name()) + "/" + a.attribute("Name").value();
      vtp.bytes[key] = inflate_array(appended, a.attribute("offset").as_ullong());
      vtp.types[key] = a.attribute("type").value();
    }
  return vtp;
}

// Three cells: a myocyte of three particles bonded in a row, two one-particle
// fibroblasts; coordinates and values that float does not hold exactly.
Tissue three_cells() {
  Tissue t;
  const int m = t.add_cell(CellType::myocyte, 10.0 / 3, 7.1);
  for (int k = 0; k < 3; ++k) t.add_particle(m, 10.0 / 3 + 8.1 * k, 7.1 + 0.01 * k, 5.05);
  t.bonds.push_back({0, 1});
  t.bonds.push_back({1, 2});
  t.add_particle(t.add_cell(CellType::fibroblast, 40.7, 1.0 / 7), 40.7, 1.0 / 7, 3.3);
  t.add_particle(t.add_cell(CellType::fibroblast, 49999.9, 49999.3), 49999.9, 49999.3, 3.3);
  return t;
}

}  // namespace

TEST_CASE("a .vtp file reads back as the tissue written: geometry exact, fields to float precision") {
  const auto dir = testing::scratch_dir("vtp_round_trip");
  const Tissue t = three_cells();
  const std::vector<double> V_mV = {-80.0 / 3, 12.345678912, std::nan("")};
  const std::vector<std::array<double, 2>> displacement = {{0.1, -0.2}, {1e-3, 0}, {0, 0}, {2.5, 1.0 / 3}, {0, 0}};
  write_tissue_vtp(t, dir / "t.vtp", {{"V mV", V_mV}}, true, &displacement);
  const VtpFile vtp = read_vtp(dir / "t.vtp");

  const pugi::xml_node piece = vtp.header.child("VTKFile").child("PolyData").child("Piece");
  CHECK(piece.attribute("NumberOfPoints").as_int() == 5);
  CHECK(piece.attribute("NumberOfVerts").as_int() == 5);
  CHECK(piece.attribute("NumberOfLines").as_int() == 2);
  CHECK(std::string(piece.child("PointData").attribute("Scalars").value()) == "V_mV");
  CHECK(vtp.types.at("PointData/cell") == "Int32");
  CHECK(vtp.types.at("PointData/cell_type") == "UInt8");
  CHECK(vtp.types.at("PointData/V_mV") == "Float32");

  // Expected: each double rounded to the nearest float (the file's Float32).
  const auto points = vtp.array<float>("Points/Points");
  const auto radius = vtp.array<float>("PointData/radius_um");
  const auto cell = vtp.array<std::int32_t>("PointData/cell");
  const auto type = vtp.array<std::uint8_t>("PointData/cell_type");
  const auto V = vtp.array<float>("PointData/V_mV");
  const auto d = vtp.array<float>("PointData/displacement_um");
  REQUIRE(points.size() == 15);
  REQUIRE(V.size() == 5);
  REQUIRE(d.size() == 15);
  for (std::size_t p = 0; p < 5; ++p) {
    CAPTURE(p);
    const Particle& q = t.particles[p];
    CHECK(points[3 * p] == static_cast<float>(q.x_um));
    CHECK(points[3 * p + 1] == static_cast<float>(q.y_um));
    CHECK(points[3 * p + 2] == 0.0f);
    CHECK(radius[p] == static_cast<float>(q.r_um));
    CHECK(cell[p] == q.cell);
    CHECK(type[p] == static_cast<std::uint8_t>(t.type[q.cell]));
    if (std::isnan(V_mV[q.cell])) CHECK(std::isnan(V[p]));
    else CHECK(V[p] == static_cast<float>(V_mV[q.cell]));
    CHECK(d[3 * p] == static_cast<float>(displacement[p][0]));
    CHECK(d[3 * p + 1] == static_cast<float>(displacement[p][1]));
    CHECK(d[3 * p + 2] == 0.0f);
  }
  CHECK(vtp.array<std::int32_t>("Verts/connectivity") == std::vector<std::int32_t>{0, 1, 2, 3, 4});
  CHECK(vtp.array<std::int32_t>("Verts/offsets") == std::vector<std::int32_t>{1, 2, 3, 4, 5});
  CHECK(vtp.array<std::int32_t>("Lines/connectivity") == std::vector<std::int32_t>{0, 1, 1, 2});
  CHECK(vtp.array<std::int32_t>("Lines/offsets") == std::vector<std::int32_t>{2, 4});

  std::vector<double> short_field(2);
  CHECK_THROWS_WITH(write_tissue_vtp(t, dir / "bad.vtp", {{"V_mV", short_field}}),
                    doctest::Contains("field 'V_mV' has 2 values for 3 cells"));
  CHECK_THROWS_WITH(write_tissue_vtp(t, dir / "no_such_dir" / "t.vtp"), doctest::Contains("cannot write"));
}

TEST_CASE("an array of several compression blocks reads back whole") {
  // 40000 particles: Points is 480000 bytes, more than seven 64 KiB blocks
  // and a partial last one.
  Tissue t;
  const int c = t.add_cell(CellType::myocyte, 0, 0);
  for (int k = 0; k < 40000; ++k) t.add_particle(c, 0.37 * k, std::sin(k), 5);
  const auto dir = testing::scratch_dir("vtp_blocks");
  write_tissue_vtp(t, dir / "big.vtp");
  const VtpFile vtp = read_vtp(dir / "big.vtp");
  const auto points = vtp.array<float>("Points/Points");
  REQUIRE(points.size() == 3 * t.particles.size());
  std::size_t differ = 0;
  for (std::size_t p = 0; p < t.particles.size(); ++p)
    differ += points[3 * p] != static_cast<float>(t.particles[p].x_um) ||
              points[3 * p + 1] != static_cast<float>(t.particles[p].y_um);
  CHECK(differ == 0);
}

TEST_CASE("legacy .vtk and XML .vtp of one tissue hold the same points, cells and values") {
  const auto dir = testing::scratch_dir("vtk_vs_vtp");
  const Tissue t = three_cells();
  const std::vector<double> activation_ms = {12.5, 101.0 / 3, 7};
  write_tissue_vtk(t, dir / "t.vtk", {{"activation_ms", activation_ms}});
  write_tissue_vtp(t, dir / "t.vtp", {{"activation_ms", activation_ms}});
  const VtpFile vtp = read_vtp(dir / "t.vtp");

  std::istringstream in(testing::read_file(dir / "t.vtk"));
  std::string word, type, line;
  for (int k = 0; k < 4; ++k) std::getline(in, line);
  std::size_t n = 0;
  in >> word >> n >> type;
  REQUIRE(word == "POINTS");
  const auto points = vtp.array<float>("Points/Points");
  REQUIRE(points.size() == 3 * n);
  for (std::size_t i = 0; i < 3 * n; ++i) {
    double x;
    in >> x;
    CHECK(points[i] == static_cast<float>(x));  // %.9g text: exact for these values, rounded as the writer rounds
  }
  std::size_t verts = 0, lines = 0, ints = 0;
  in >> word >> verts >> ints;
  CHECK(word == "VERTICES");
  CHECK(verts == vtp.array<std::int32_t>("Verts/offsets").size());
  for (std::size_t i = 0; i < ints; ++i) in >> word;
  in >> word >> lines >> ints;
  CHECK(word == "LINES");
  CHECK(lines == vtp.array<std::int32_t>("Lines/offsets").size());
  for (std::size_t i = 0; i < ints; ++i) in >> word;
  in >> word >> n;
  CHECK(word == "POINT_DATA");
  // Each SCALARS block against the .vtp array of the same name.
  std::size_t arrays = 0;
  while (in >> word && word == "SCALARS") {
    std::string name;
    in >> name >> type >> word >> word >> word;  // "1", "LOOKUP_TABLE", "default"
    CAPTURE(name);
    const std::string key = "PointData/" + name;
    REQUIRE(vtp.types.count(key) == 1);
    for (std::size_t i = 0; i < n; ++i) {
      double x;
      in >> x;
      if (vtp.types.at(key) == "Float32") CHECK(vtp.array<float>(key)[i] == static_cast<float>(x));
      else if (vtp.types.at(key) == "Int32") CHECK(vtp.array<std::int32_t>(key)[i] == static_cast<std::int32_t>(x));
      else CHECK(vtp.array<std::uint8_t>(key)[i] == static_cast<std::uint8_t>(x));
    }
    ++arrays;
  }
  CHECK(arrays == 4);  // radius_um, cell, cell_type, activation_ms
  CHECK(vtp.bytes.count("PointData/activation_ms") == 1);
}

TEST_CASE("files of a tissue larger than the writers' buffers hold every particle, bond, field and displacement") {
  // 6000 cells of 6 particles bonded in a row: each .vtp array spans several
  // 64 KiB blocks, the legacy text ~2 MB, many times the 64 kB it is
  // written out by. Expected values: the tissue's own, as each format rounds them.
  Tissue t;
  for (int c = 0; c < 6000; ++c) {
    const int cell = t.add_cell(c % 10 ? CellType::myocyte : CellType::fibroblast, 0.1 * c, 1.0 / (c + 3));
    for (int k = 0; k < 6; ++k) {
      t.add_particle(cell, 0.1 * c + 16.7 * k, 1.0 / (c + 3) + k, 12.5);
      if (k > 0) t.bonds.push_back({6 * c + k - 1, 6 * c + k});
    }
  }
  std::vector<double> field(t.cell_count());
  for (std::size_t c = 0; c < field.size(); ++c) field[c] = std::sqrt(static_cast<double>(c) + 0.5);
  std::vector<std::array<double, 2>> displacement(t.particles.size());
  for (std::size_t p = 0; p < displacement.size(); ++p) displacement[p] = {0.001 * p, -1.0 / (p + 1)};
  const auto dir = testing::scratch_dir("vtk_streamed");
  write_tissue_vtp(t, dir / "t.vtp", {{"V_mV", field}}, true, &displacement);
  write_tissue_vtk(t, dir / "t.vtk", {{"V_mV", field}}, true, &displacement);

  const VtpFile vtp = read_vtp(dir / "t.vtp");
  const std::size_t n = t.particles.size();
  const auto points = vtp.array<float>("Points/Points");
  const auto cell = vtp.array<std::int32_t>("PointData/cell");
  const auto v = vtp.array<float>("PointData/V_mV");
  const auto d = vtp.array<float>("PointData/displacement_um");
  const auto ends = vtp.array<std::int32_t>("Lines/connectivity");
  REQUIRE(points.size() == 3 * n);
  REQUIRE(cell.size() == n);
  REQUIRE(v.size() == n);
  REQUIRE(d.size() == 3 * n);
  REQUIRE(ends.size() == 2 * t.bonds.size());
  std::size_t differ = 0;
  for (std::size_t p = 0; p < n; ++p) {
    const Particle& q = t.particles[p];
    differ += points[3 * p] != static_cast<float>(q.x_um) || points[3 * p + 1] != static_cast<float>(q.y_um) ||
              cell[p] != q.cell || v[p] != static_cast<float>(field[static_cast<std::size_t>(q.cell)]) ||
              d[3 * p] != static_cast<float>(displacement[p][0]) ||
              d[3 * p + 1] != static_cast<float>(displacement[p][1]) || d[3 * p + 2] != 0.0f;
  }
  for (std::size_t b = 0; b < t.bonds.size(); ++b)
    differ += ends[2 * b] != t.bonds[b].p || ends[2 * b + 1] != t.bonds[b].q;
  CHECK(differ == 0);

  // The legacy file: its last section, the displacement, read back whole
  // (%.9g text: nine significant digits, within 5e-9 relative of the values).
  const std::string text = testing::read_file(dir / "t.vtk");
  const std::size_t at = text.find("VECTORS displacement_um double\n");
  REQUIRE(at != std::string::npos);
  std::istringstream in(text.substr(at + 31));
  std::size_t read = 0, off = 0;
  double x, y, z;
  while (in >> x >> y >> z) {
    REQUIRE(read < n);
    off += std::abs(x - displacement[read][0]) > 5e-9 * std::abs(displacement[read][0]) ||
           std::abs(y - displacement[read][1]) > 5e-9 * std::abs(displacement[read][1]) || z != 0;
    ++read;
  }
  CHECK(read == n);
  CHECK(off == 0);
}

namespace {
std::vector<std::pair<double, std::string>> read_pvd(const std::filesystem::path& file) {
  pugi::xml_document doc;
  REQUIRE(doc.load_file(file.c_str()));
  CHECK(std::string(doc.child("VTKFile").attribute("type").value()) == "Collection");
  std::vector<std::pair<double, std::string>> entries;
  for (const pugi::xml_node d : doc.child("VTKFile").child("Collection").children("DataSet"))
    entries.emplace_back(d.attribute("timestep").as_double(), d.attribute("file").value());
  return entries;
}
}  // namespace

TEST_CASE("a .pvd collection lists its files by time, valid after every addition") {
  const auto dir = testing::scratch_dir("pvd");
  const auto pvd = dir / "s.pvd";
  add_to_pvd(pvd, 2.5, "b.vtp");
  CHECK(read_pvd(pvd) == std::vector<std::pair<double, std::string>>{{2.5, "b.vtp"}});
  add_to_pvd(pvd, 0.01, "a.vtp");
  add_to_pvd(pvd, 2.5, "b.vtp");  // written again (a resumed run): listed once
  add_to_pvd(pvd, 1.0 / 3, "c.vtp");
  CHECK(read_pvd(pvd) ==
        std::vector<std::pair<double, std::string>>{{0.01, "a.vtp"}, {1.0 / 3, "c.vtp"}, {2.5, "b.vtp"}});
  CHECK_FALSE(std::filesystem::exists(dir / "s.pvd.tmp"));
  {
    std::ofstream(dir / "broken.pvd") << "<VTKFile><Collection>";
  }
  CHECK_THROWS_WITH(add_to_pvd(dir / "broken.pvd", 1, "a.vtp"), doctest::Contains("broken.pvd cannot be read"));
}

TEST_CASE("output.vtk_format xml: a run writes .vtp files and snapshots.pvd lists each snapshot at its time") {
  json m = testing::passive_cell_manifest();
  m["duration_ms"] = 6;
  m["tissue"] = {{"builder", "strand"}, {"type", "fibroblast"}, {"cells", 4}};
  m["output"]["vtk_format"] = "xml";
  m["output"]["maps"] = true;
  m["output"]["tissue_picture"] = true;
  m["output"]["report"] = false;
  m["output"]["snapshots"] = {{"every_ms", 2}, {"png", false}};
  const auto dir = testing::scratch_dir("vtk_format_xml");
  m["output"]["dir"] = dir.string();
  Simulation(parse_scene(m)).run();

  for (const char* name : {"tissue.vtp", "maps.vtp"}) CHECK(std::filesystem::exists(dir / name));
  std::size_t vtp_snapshots = 0, vtk_files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    vtp_snapshots += name.rfind("snapshot_", 0) == 0 && entry.path().extension() == ".vtp";
    vtk_files += entry.path().extension() == ".vtk";
  }
  CHECK(vtk_files == 0);
  // Snapshots at the first step's end (0.01 ms, dt of the manifest) and at 2, 4, 6 ms.
  const auto entries = read_pvd(dir / "snapshots.pvd");
  REQUIRE(entries.size() == 4);
  CHECK(vtp_snapshots == 4);
  const double expected_ms[] = {0.01, 2, 4, 6};
  for (std::size_t k = 0; k < entries.size(); ++k) {
    CAPTURE(entries[k].second);
    CHECK(entries[k].first == doctest::Approx(expected_ms[k]).epsilon(1e-9));
    CHECK(std::filesystem::exists(dir / entries[k].second));
    // The file's name carries the same time (snapshot_<t>_ms.vtp, t to 1 us).
    CHECK(std::stod(entries[k].second.substr(9)) == doctest::Approx(entries[k].first).epsilon(1e-6));
    const VtpFile vtp = read_vtp(dir / entries[k].second);
    CHECK(vtp.array<float>("PointData/V_mV").size() == 4);
  }
}

TEST_CASE("a run killed and resumed keeps one snapshots.pvd listing every snapshot once") {
  // `fibrodem run` killed (SIGKILL, FIBRODEM_TEST_KILL) at step 450 of 600
  // (t = 4.5 ms), then `fibrodem resume` from its last checkpoint (4 ms).
  json m = testing::passive_cell_manifest();
  m["duration_ms"] = 6;
  m["tissue"] = {{"builder", "strand"}, {"type", "fibroblast"}, {"cells", 4}};
  m["output"]["vtk_format"] = "xml";
  m["output"]["report"] = false;
  m["output"]["snapshots"] = {{"every_ms", 2}, {"png", false}};
  m["output"]["checkpoint"] = {{"every_ms", 1}};
  const auto dir = testing::scratch_dir("vtk_format_xml_resumed");
  const auto out = dir / "run";
  std::ofstream(dir / "m.json") << m.dump();
  const std::string exe = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem";
  REQUIRE(std::system(("FIBRODEM_TEST_KILL=step:450 " + exe + " run --quiet " + (dir / "m.json").string() +
                       " --out " + out.string() + " > /dev/null 2>&1").c_str()) != 0);
  REQUIRE(std::system((exe + " resume --quiet " + out.string() + " > /dev/null 2>&1").c_str()) == 0);
  const json summary = json::parse(testing::read_file(out / "summary.json"));
  CHECK(summary["resumed_from"]["time_ms"].get<double>() == 4.0);
  const auto entries = read_pvd(out / "snapshots.pvd");
  REQUIRE(entries.size() == 4);
  const double expected_ms[] = {0.01, 2, 4, 6};
  for (std::size_t k = 0; k < entries.size(); ++k) {
    CAPTURE(entries[k].second);
    CHECK(entries[k].first == doctest::Approx(expected_ms[k]).epsilon(1e-9));
    CHECK(std::filesystem::exists(out / entries[k].second));
  }
}
