// A CSV file written row by row and flushed as the run goes, so that a run
// that fails or is killed keeps what it had. Numbers are written with 17
// significant digits (round-trip exact, byte-identical across runs).
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "util/number_text.hpp"

namespace fibrodem {

class CsvWriter {
 public:
  CsvWriter() = default;
  CsvWriter(const std::filesystem::path& file, const std::vector<std::string>& header);
  // Continues a file written before (a resumed run): cut back to its first
  // `bytes` bytes (what was flushed at the checkpoint), then appended to.
  // Throws std::runtime_error naming the file if it is shorter than that.
  static CsvWriter resume(const std::filesystem::path& file, std::uintmax_t bytes);

  bool is_open() const { return out_.is_open(); }
  // Starts a row; then cell(...) for each column, then end_row().
  CsvWriter& cell(double value);
  CsvWriter& cell(long long value);
  CsvWriter& cell(const std::string& value);
  void end_row();
  // Throws std::runtime_error naming the file if anything written so far
  // could not be (a full disk): the run then stops as failed.
  void flush();
  // Bytes in the file after a flush() (a checkpoint records it).
  std::uintmax_t bytes_written();

 private:
  std::filesystem::path file_;
  std::ofstream out_;
  bool first_in_row_ = true;
};

}  // namespace fibrodem
