// A checkpoint file: a run's complete state at one time, as named fields of
// numbers, in a versioned binary format with a checksum
// (docs/guide/checkpoints.md). Layout, little-endian:
//   "FIBRODEM-CHECKPOINT" \n      20 bytes, the magic
//   u32 format version            kCheckpointFormat
//   u64 payload length
//   payload: u32 field count, then per field
//     u16 name length, name, u8 kind (0 f64, 1 i64, 2 bytes), u64 count, data
//   32 bytes SHA-256 of everything before it
// Each part of a run (cells, biomarker trackers, traces, DEM bodies, ...)
// writes its fields under its own prefix and reads them back by name, so a
// reader names exactly what is missing or of the wrong size.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace fibrodem {

inline constexpr std::uint32_t kCheckpointFormat = 1;

// A checkpoint that cannot be read or does not fit the scene: the message
// names the file (when known) and the fault.
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class CheckpointFields {
 public:
  void put(const std::string& name, const std::vector<double>& values);
  void put(const std::string& name, const std::vector<long long>& values);
  void put(const std::string& name, const std::vector<int>& values);
  void put(const std::string& name, double value) { put(name, std::vector<double>{value}); }
  void put_integer(const std::string& name, long long value) { put(name, std::vector<long long>{value}); }
  void put_text(const std::string& name, const std::string& text);
  void put_bytes(const std::string& name, const void* data, std::size_t size);

  bool has(const std::string& name) const { return fields_.count(name) != 0; }
  // The names of the fields that begin with `prefix`, in order.
  std::vector<std::string> names_starting(const std::string& prefix) const;
  // Field `name` of `other`, as it is there (a run's checkpoint taken apart
  // and put together again: run/checkpoint_recut.hpp).
  // Throws CheckpointError if `other` has no such field.
  void copy_from(const CheckpointFields& other, const std::string& name);
  // Each getter throws CheckpointError naming the field if it is missing, of
  // another kind, or (with `expected`) of another length.
  std::vector<double> numbers(const std::string& name, long long expected = -1) const;
  std::vector<long long> integers(const std::string& name, long long expected = -1) const;
  std::vector<int> ints(const std::string& name, long long expected = -1) const;
  double number(const std::string& name) const { return numbers(name, 1)[0]; }
  long long integer(const std::string& name) const { return integers(name, 1)[0]; }
  std::string text(const std::string& name) const;
  // Copies exactly `size` bytes into data.
  void bytes(const std::string& name, void* data, std::size_t size) const;

  // Reads into an existing vector, requiring its present length.
  void read_into(const std::string& name, std::vector<double>& values) const {
    values = numbers(name, static_cast<long long>(values.size()));
  }

  // The encoded file (header, payload, checksum), handed to `write` in
  // order, piece by piece: the fields' data as they are held, so that
  // writing a checkpoint copies none of it (a copy of the payload would
  // double a checkpoint's memory while it is written).
  void encode_into(const std::function<void(std::string_view)>& write) const;
  std::uint64_t encoded_size() const;  // bytes, checksum included
  // The same in one string, and its inverse; decode throws CheckpointError
  // for a wrong magic, format, length or checksum.
  std::string encode() const;
  static CheckpointFields decode(std::string_view file_bytes);
  // The fields of a payload taken from `source` (checkpoint_file.cpp: from
  // a string in memory, or from the file as it is read).
  template <class Source>
  static CheckpointFields parse_payload(Source& source);

 private:
  enum Kind : std::uint8_t { kF64 = 0, kI64 = 1, kBytes = 2 };
  struct Field {
    Kind kind;
    std::uint64_t count;
    std::string data;
  };
  const Field& field(const std::string& name, Kind kind) const;
  std::uint64_t payload_size() const;
  std::map<std::string, Field> fields_;
};

// Writes atomically: a temporary file beside it, flushed to disk, then
// renamed over `file` (a kill at any moment leaves the old file or the new,
// never half of one). Throws std::runtime_error naming the file on failure.
// `midway`, if given, runs when half the temporary file is written (tests
// kill the process there).
void write_checkpoint_file(const std::filesystem::path& file, const CheckpointFields& fields,
                           const std::function<void()>& midway = nullptr);
// Throws CheckpointError naming the file: unreadable, truncated, corrupt.
CheckpointFields read_checkpoint_file(const std::filesystem::path& file);

}  // namespace fibrodem
