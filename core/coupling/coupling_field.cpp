#include "coupling/coupling_field.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "coupling/coupling_region.hpp"

namespace fibrodem {

namespace {

// A sample's value: finite and >= 0, else an error naming where it is.
double checked_value(double value, const std::string& where) {
  if (!std::isfinite(value) || value < 0)
    throw ManifestError(where, fmt::format("expected a scale >= 0, got {}", value));
  return value;
}

// The grid's rows as written inline: a list of lists of numbers.
std::vector<std::vector<double>> inline_rows(const json& rows, const std::string& path) {
  if (!rows.is_array() || rows.empty())
    throw ManifestError(path, "expected a list of rows (each a list of numbers), got " + describe_json(rows));
  std::vector<std::vector<double>> out;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::string row_path = index_path(path, i);
    if (!rows[i].is_array() || rows[i].empty())
      throw ManifestError(row_path, "expected a row: a list of numbers, got " + describe_json(rows[i]));
    std::vector<double>& row = out.emplace_back();
    for (std::size_t j = 0; j < rows[i].size(); ++j) {
      if (!rows[i][j].is_number())
        throw ManifestError(index_path(row_path, j), "expected a number, got " + describe_json(rows[i][j]));
      row.push_back(checked_value(rows[i][j].get<double>(), index_path(row_path, j)));
    }
  }
  return out;
}

// The grid's rows from a CSV file; errors name the file's line.
std::vector<std::vector<double>> file_rows(const std::string& file, const std::string& path) {
  std::ifstream in(file);
  if (!in) throw ManifestError(path, "cannot read the file \"" + file + "\"");
  std::vector<std::vector<double>> out;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    const std::string where = fmt::format("{} (\"{}\" line {})", path, file, number);
    std::vector<double>& row = out.emplace_back();
    std::istringstream cells(line);
    std::string cell;
    for (int column = 1; std::getline(cells, cell, ','); ++column) {
      std::size_t used = 0;
      double value = 0;
      try {
        value = std::stod(cell, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || cell.find_first_not_of(" \t", used) != std::string::npos)
        throw ManifestError(where, fmt::format("value {}: expected a number, got \"{}\"", column, cell));
      row.push_back(checked_value(value, fmt::format("{} value {}", where, column)));
    }
    if (row.empty()) throw ManifestError(where, "expected a row of numbers separated by commas");
  }
  if (out.empty()) throw ManifestError(path, "the file \"" + file + "\" holds no row of numbers");
  return out;
}

// Position of a coordinate on the grid's axis of `count` samples over [lo, hi]:
// 0 at lo, count - 1 at hi.
double grid_position(double at, double lo, double hi, int count) {
  return count == 1 ? 0.0 : std::clamp((at - lo) / (hi - lo), 0.0, 1.0) * (count - 1);
}

}  // namespace

double CouplingField::scale_at(double x_um, double y_um) const {
  const double u = grid_position(x_um, x_min_um, x_max_um, columns);
  const double v = grid_position(y_um, y_min_um, y_max_um, rows);
  auto at = [&](int row, int column) { return scale[static_cast<std::size_t>(row) * columns + column]; };
  if (between == Between::nearest) return at(static_cast<int>(std::lround(v)), static_cast<int>(std::lround(u)));
  const int c0 = std::min(static_cast<int>(u), columns - 1), r0 = std::min(static_cast<int>(v), rows - 1);
  const int c1 = std::min(c0 + 1, columns - 1), r1 = std::min(r0 + 1, rows - 1);
  const double fu = u - c0, fv = v - r0;
  return (1 - fv) * ((1 - fu) * at(r0, c0) + fu * at(r0, c1)) + fv * ((1 - fu) * at(r1, c0) + fu * at(r1, c1));
}

CouplingField read_coupling_field(const json& object, const std::string& path) {
  if (!object.is_object()) throw ManifestError(path, "expected a field object, got " + describe_json(object));
  JsonReader r(object, path);
  CouplingField field;
  field.path = path;
  read_span_mm(r, "x_mm", field.x_min_um, field.x_max_um);
  read_span_mm(r, "y_mm", field.y_min_um, field.y_max_um);
  if (r.has("scale") == r.has("file"))
    throw ManifestError(path, r.has("scale") ? "expected either scale (the grid inline) or file (a CSV), got both"
                                             : "expected scale (the grid inline) or file (a CSV), got neither");
  const std::vector<std::vector<double>> rows =
      r.has("scale") ? inline_rows(r.raw("scale"), r.path_of("scale"))
                     : file_rows(r.text("file", std::nullopt), r.path_of("file"));
  field.between = r.text("between", std::string("bilinear"), {"bilinear", "nearest"}) == "nearest"
                      ? CouplingField::Between::nearest
                      : CouplingField::Between::bilinear;
  r.finish();
  field.rows = static_cast<int>(rows.size());
  field.columns = static_cast<int>(rows.front().size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (static_cast<int>(rows[i].size()) != field.columns)
      throw ManifestError(path, fmt::format("row {} has {} values, the first row {}: every row of the grid needs as many",
                                            i + 1, rows[i].size(), field.columns));
    field.scale.insert(field.scale.end(), rows[i].begin(), rows[i].end());
  }
  return field;
}

}  // namespace fibrodem
