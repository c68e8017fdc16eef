// A CSV file written row by row and flushed as the run goes, so that a run
// that fails or is killed keeps what it had. Numbers are written with 17
// significant digits (round-trip exact, byte-identical across runs).
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fibrodem {

class CsvWriter {
 public:
  CsvWriter() = default;
  CsvWriter(const std::filesystem::path& file, const std::vector<std::string>& header);

  bool is_open() const { return out_.is_open(); }
  // Starts a row; then cell(...) for each column, then end_row().
  CsvWriter& cell(double value);
  CsvWriter& cell(long long value);
  CsvWriter& cell(const std::string& value);
  void end_row();
  // Throws std::runtime_error naming the file if anything written so far
  // could not be (a full disk): the run then stops as failed.
  void flush();

 private:
  std::filesystem::path file_;
  std::ofstream out_;
  bool first_in_row_ = true;
};

std::string format_number(double value);  // shortest exact text; "nan", "inf"

}  // namespace fibrodem
