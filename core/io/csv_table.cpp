#include "io/csv_table.hpp"

#include <cstdlib>
#include <limits>

namespace fibrodem {

namespace {

// `line` split at its commas into `cells`, reusing their storage.
void split(const std::string& line, std::vector<std::string>& cells) {
  std::size_t count = 0, start = 0;
  auto put = [&](std::size_t end) {
    if (count == cells.size()) cells.emplace_back();
    cells[count++].assign(line, start, end - start);
  };
  for (std::size_t comma = line.find(','); comma != std::string::npos; comma = line.find(',', start)) {
    put(comma);
    start = comma + 1;
  }
  put(line.size());
  cells.resize(count);
}

}  // namespace

double csv_number(const std::string& text) {
  if (text.empty()) return std::numeric_limits<double>::quiet_NaN();
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  return end != nullptr && *end == '\0' ? v : std::numeric_limits<double>::quiet_NaN();
}

std::optional<std::size_t> csv_column(const std::vector<std::string>& header, const std::string& name) {
  for (std::size_t c = 0; c < header.size(); ++c)
    if (header[c] == name) return c;
  return std::nullopt;
}

std::optional<std::size_t> CsvTable::column(const std::string& name) const { return csv_column(header, name); }

std::vector<double> CsvTable::numbers(std::size_t column) const {
  std::vector<double> out;
  out.reserve(rows.size());
  for (const auto& row : rows) out.push_back(csv_number(row[column]));
  return out;
}

CsvRowReader::CsvRowReader(const std::filesystem::path& file) {
  // A regular file only: a device in its place (a test's /dev/full) would
  // read forever.
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) return;
  in_.open(file);
  if (!in_ || !std::getline(in_, line_) || line_.empty()) return;
  split(line_, header_);
  ok_ = true;
}

bool CsvRowReader::next(std::vector<std::string>& cells) {
  if (!ok_) return false;
  while (std::getline(in_, line_)) {
    if (line_.empty()) continue;
    split(line_, cells);
    // A line cut short (a killed run) is not counted, nor is its last cell.
    if (cells.size() != header_.size() || in_.eof()) {
      ++skipped_rows_;
      continue;
    }
    return true;
  }
  return false;
}

std::optional<CsvTable> read_csv_table(const std::filesystem::path& file) {
  CsvRowReader reader(file);
  if (!reader.ok()) return std::nullopt;
  CsvTable table;
  table.header = reader.header();
  for (std::vector<std::string> cells; reader.next(cells);) table.rows.push_back(cells);
  table.skipped_rows = reader.skipped_rows();
  return table;
}

}  // namespace fibrodem
