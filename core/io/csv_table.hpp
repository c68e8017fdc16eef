// A CSV file as written by CsvWriter: a header and rows of plain cells (no
// quoting: CsvWriter writes none). A run that was killed may leave a last line
// half written; rows whose cell count differs from the header's are skipped
// and counted. Read whole (CsvTable) or row by row (CsvRowReader: a file too
// large to hold, such as biomarkers.csv of a large tissue).
#pragma once

#include <filesystem>
#include <fstream>
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

// A cell as a number: NaN if it is empty or not a number.
double csv_number(const std::string& cell);

// The index of the column named `name` in a header, if it has one.
std::optional<std::size_t> csv_column(const std::vector<std::string>& header, const std::string& name);

// The rows of a file one at a time; the same rows read_csv_table keeps.
class CsvRowReader {
 public:
  explicit CsvRowReader(const std::filesystem::path& file);
  // false if the file is not a regular file, cannot be opened or has no
  // header line.
  bool ok() const { return ok_; }
  const std::vector<std::string>& header() const { return header_; }
  // The next whole row into `cells` (its storage reused); false at the end.
  bool next(std::vector<std::string>& cells);
  std::size_t skipped_rows() const { return skipped_rows_; }

 private:
  std::ifstream in_;
  std::string line_;
  std::vector<std::string> header_;
  std::size_t skipped_rows_ = 0;
  bool ok_ = false;
};

// nullopt if the file is not a regular file, cannot be opened or has no
// header line.
std::optional<CsvTable> read_csv_table(const std::filesystem::path& file);

}  // namespace fibrodem
