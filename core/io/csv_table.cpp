#include "io/csv_table.hpp"

#include <cstdlib>
#include <fstream>
#include <limits>

namespace fibrodem {

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::size_t start = 0;
  for (std::size_t comma = line.find(','); comma != std::string::npos; comma = line.find(',', start)) {
    cells.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
  cells.push_back(line.substr(start));
  return cells;
}

double number_of(const std::string& text) {
  if (text.empty()) return std::numeric_limits<double>::quiet_NaN();
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  return end != nullptr && *end == '\0' ? v : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

std::optional<std::size_t> CsvTable::column(const std::string& name) const {
  for (std::size_t c = 0; c < header.size(); ++c)
    if (header[c] == name) return c;
  return std::nullopt;
}

std::vector<double> CsvTable::numbers(std::size_t column) const {
  std::vector<double> out;
  out.reserve(rows.size());
  for (const auto& row : rows) out.push_back(number_of(row[column]));
  return out;
}

std::optional<CsvTable> read_csv_table(const std::filesystem::path& file) {
  // A regular file only: a device in its place (a test's /dev/full) would
  // read forever.
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) return std::nullopt;
  std::ifstream in(file);
  std::string line;
  if (!in || !std::getline(in, line) || line.empty()) return std::nullopt;
  CsvTable table;
  table.header = split(line);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    auto cells = split(line);
    // A line cut short (a killed run) is not counted, nor is its last cell.
    if (cells.size() != table.header.size() || in.eof()) {
      ++table.skipped_rows;
      continue;
    }
    table.rows.push_back(std::move(cells));
  }
  return table;
}

}  // namespace fibrodem
