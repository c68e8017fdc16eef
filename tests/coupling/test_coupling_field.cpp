// coupling.field: a grid of conductance scale factors, sampled at each
// junction's midpoint. Known answers: the sampler reproduces a function
// linear in x and y exactly and picks the nearest sample; a field of one
// value is a region of that scale, bit for bit; the same grid inline or from
// a file gives the same bits; on a strand whose conductance falls linearly
// the wave slows as strands of the local conductance do; bad fields are named.
#include <doctest/doctest.h>

#include <fstream>
#include <iomanip>

#include "coupling/coupling_field.hpp"
#include "coupling/gap_junction.hpp"
#include "support/paced_strand.hpp"

using namespace fibrodem;

namespace {

// Activation times of every cell, in cell order.
std::vector<double> activations(const json& m) {
  Simulation sim(parse_scene(m));
  sim.run();
  std::vector<double> t;
  for (const auto& b : sim.biomarkers()) t.push_back(b.activation_ms);
  return t;
}

// CV [cm/s] over [from, to] mm of a run of `m`.
double cv_between(const json& m, double from_mm, double to_mm) {
  Simulation sim(parse_scene(m));
  sim.run();
  return testing::cv_between(sim, from_mm, to_mm);
}

std::string error_of(const json& m) {
  try {
    Simulation sim(parse_scene(m));
  } catch (const ManifestError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("the field's sampler: bilinear is exact for a plane, nearest picks the closest sample") {
  // 3 columns over x [0, 2] mm, 2 rows over y [0, 1] mm of f = 1 + x + 2 y (mm).
  const json grid = {{"x_mm", {0, 2}}, {"y_mm", {0, 1}}, {"scale", {{1, 2, 3}, {3, 4, 5}}}};
  const CouplingField bilinear = read_coupling_field(grid, "coupling.field");
  CHECK(bilinear.rows == 2);
  CHECK(bilinear.columns == 3);
  for (double x : {0.0, 0.3, 1.0, 1.7, 2.0})
    for (double y : {0.0, 0.25, 0.9, 1.0}) CHECK(bilinear.scale_at(x * 1000, y * 1000) == doctest::Approx(1 + x + 2 * y));
  json near = grid;
  near["between"] = "nearest";
  const CouplingField nearest = read_coupling_field(near, "coupling.field");
  CHECK(nearest.scale_at(400, 200) == 1);   // sample (0, 0)
  CHECK(nearest.scale_at(600, 200) == 2);   // sample (1, 0)
  CHECK(nearest.scale_at(1600, 700) == 5);  // sample (2, 1)
  // One row: constant along y.
  const CouplingField row = read_coupling_field({{"x_mm", {0, 1}}, {"y_mm", {0, 5}}, {"scale", {{2, 4}}}}, "f");
  CHECK(row.scale_at(500, 0) == 3);
  CHECK(row.scale_at(500, 4000) == 3);
  CHECK(row.contains(1000, 5000));
  CHECK_FALSE(row.contains(1000.001, 5000));
}

TEST_CASE("a field of one value is a region of that scale, bit for bit, and a file gives the inline grid's bits") {
  json region = testing::paced_strand(40);
  region["coupling"]["regions"] = json::array({{{"shape", "rectangle"}, {"x_mm", {-1, 1}}, {"y_mm", {2, 3.5}}, {"scale", 0.3}}});
  json field = testing::paced_strand(40);
  field["coupling"]["field"] = {{"x_mm", {-1, 1}}, {"y_mm", {2, 3.5}}, {"scale", {{0.3}}}};
  const std::vector<double> by_region = activations(region);
  CHECK(activations(field) == by_region);
  // The same through the section's D_m_nS (scale 0.3 over the whole strand).
  json whole = testing::paced_strand(40), slower = testing::paced_strand(40);
  whole["coupling"]["field"] = {{"x_mm", {-1, 1}}, {"y_mm", {-1, 6}}, {"scale", {{0.25, 0.25}, {0.25, 0.25}}}};
  slower["coupling"]["D_m_nS"] = 250;
  CHECK(activations(whole) == activations(slower));
  // A grid written to a CSV file, with a comment and a blank line.
  const auto csv = testing::scratch_dir("coupling_field") / "scale.csv";
  std::ofstream(csv) << "# a 3 x 2 map\n1,0.5\n\n0.4, 0.8\n0.2,1.5\n";
  json inline_grid = testing::paced_strand(40), from_file = testing::paced_strand(40);
  inline_grid["coupling"]["field"] = {{"x_mm", {-1, 1}}, {"y_mm", {0, 5}}, {"scale", {{1, 0.5}, {0.4, 0.8}, {0.2, 1.5}}}};
  from_file["coupling"]["field"] = {{"x_mm", {-1, 1}}, {"y_mm", {0, 5}}, {"file", csv.string()}};
  const std::vector<double> from_inline = activations(inline_grid);
  CHECK(activations(from_file) == from_inline);
  CHECK(from_inline != activations(testing::paced_strand(40)));
}

TEST_CASE("coupling.field: a strand whose conductance falls linearly conducts at each point as a uniform strand of the local conductance") {
  // 1000 nS at y = 0 falling to 250 nS at y = 10 mm; at 5 mm the map gives
  // 625 nS. The fit over 4.5-5.5 mm against a uniform 625 nS strand's over
  // the same cells: the gradient is gentle (7.5 % of D a mm), so within 3 %.
  json graded = testing::paced_strand(80);
  graded["coupling"]["field"] = {{"x_mm", {-1, 1}}, {"y_mm", {0, 10}}, {"scale", {{1.0}, {0.25}}}};
  json uniform = testing::paced_strand(80);
  uniform["coupling"]["D_m_nS"] = 625;
  const double cv_graded = cv_between(graded, 4.5, 5.5), cv_uniform = cv_between(uniform, 4.5, 5.5);
  const double cv_start = cv_between(graded, 1.5, 2.5), cv_end = cv_between(graded, 7.5, 8.5);
  MESSAGE(std::setprecision(6), "CV at 2 mm ", cv_start, ", 5 mm ", cv_graded, " (uniform 625 nS: ", cv_uniform,
          "), 8 mm ", cv_end, " cm/s");
  CHECK(cv_graded == doctest::Approx(cv_uniform).epsilon(0.03));
  CHECK(cv_start > cv_graded);
  CHECK(cv_graded > cv_end);
}

TEST_CASE("coupling.field: bad fields are named") {
  json m = testing::paced_strand(10);
  const auto with_field = [&](const json& field) {
    m["coupling"]["field"] = field;
    return error_of(m);
  };
  const json at = {{"x_mm", {-1, 1}}, {"y_mm", {0, 1}}};
  json ragged = at;
  ragged["scale"] = {{1, 2}, {3}};
  CHECK(with_field(ragged).find("coupling.field: row 2 has 1 values, the first row 2") != std::string::npos);
  json negative = at;
  negative["scale"] = {{1, -0.5}};
  CHECK(with_field(negative).find("coupling.field.scale[0][1]: expected a scale >= 0, got -0.5") != std::string::npos);
  json both = at;
  both["scale"] = {{1}};
  both["file"] = "x.csv";
  CHECK(with_field(both).find("got both") != std::string::npos);
  CHECK(with_field(at).find("got neither") != std::string::npos);
  json missing = at;
  missing["file"] = "/nonexistent/scale.csv";
  CHECK(with_field(missing).find("coupling.field.file: cannot read the file \"/nonexistent/scale.csv\"") !=
        std::string::npos);
  const auto csv = testing::scratch_dir("coupling_field_bad") / "bad.csv";
  std::ofstream(csv) << "1,2\n1,two\n";
  json bad_number = at;
  bad_number["file"] = csv.string();
  CHECK(with_field(bad_number).find("line 2): value 2: expected a number, got \"two\"") != std::string::npos);
  json off = {{"x_mm", {5, 6}}, {"y_mm", {0, 1}}, {"scale", {{1}}}};
  CHECK(with_field(off).find("coupling.field: holds no junction") != std::string::npos);
}
