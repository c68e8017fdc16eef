// A CSV file as written by CsvWriter, read back whole: a header and rows of
// plain cells (no quoting: CsvWriter writes none). A run that was killed may
// leave a last line half written; rows whose cell count differs from the
// header's are skipped and counted.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace fibrodem {

struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::size_t skipped_rows = 0;

  // The column's index, if the header has it.
  std::optional<std::size_t> column(const std::string& name) const;
  // The column as numbers (NaN where a cell is empty or not a number).
  std::vector<double> numbers(std::size_t column) const;
};

// nullopt if the file is not a regular file, cannot be opened or has no
// header line.
std::optional<CsvTable> read_csv_table(const std::filesystem::path& file);

}  // namespace fibrodem
