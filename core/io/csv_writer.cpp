#include "io/csv_writer.hpp"

#include <cmath>
#include <stdexcept>

namespace fibrodem {

CsvWriter::CsvWriter(const std::filesystem::path& file, const std::vector<std::string>& header)
    : file_(file), out_(file, std::ios::trunc) {
  if (!out_) throw std::runtime_error("cannot write " + file.string());
  for (const auto& h : header) cell(h);
  end_row();
}

CsvWriter CsvWriter::resume(const std::filesystem::path& file, std::uintmax_t bytes) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec || size < bytes)
    throw std::runtime_error("cannot resume " + file.string() + ": " +
                             (ec ? ec.message() : "it has " + std::to_string(size) + " bytes, the checkpoint saw " +
                                                      std::to_string(bytes)));
  std::filesystem::resize_file(file, bytes);
  CsvWriter w;
  w.file_ = file;
  w.out_.open(file, std::ios::app);
  if (!w.out_) throw std::runtime_error("cannot write " + file.string());
  return w;
}

std::uintmax_t CsvWriter::bytes_written() {
  flush();
  return static_cast<std::uintmax_t>(out_.tellp());
}

// A text holding a comma, a quote or a line break is quoted, its quotes
// doubled (RFC 4180): a sweep's list-valued grid column stays one column.
CsvWriter& CsvWriter::cell(const std::string& value) {
  if (!first_in_row_) out_ << ',';
  if (value.find_first_of(",\"\r\n") == std::string::npos) {
    out_ << value;
  } else {
    out_ << '"';
    for (char c : value) out_ << (c == '"' ? "\"\"" : std::string(1, c));
    out_ << '"';
  }
  first_in_row_ = false;
  return *this;
}

CsvWriter& CsvWriter::cell(double value) { return cell(format_number(value)); }

CsvWriter& CsvWriter::cell(long long value) { return cell(std::to_string(value)); }

void CsvWriter::flush() {
  out_.flush();
  if (!out_) throw std::runtime_error("writing " + file_.string() + " failed (is the disk full?)");
}

void CsvWriter::end_row() {
  out_ << '\n';
  first_in_row_ = true;
}

}  // namespace fibrodem
