#include "io/checkpoint_file.hpp"

#include "util/sha256.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>

namespace fibrodem {

namespace {

constexpr char kMagic[] = "FIBRODEM-CHECKPOINT\n";  // 20 characters
constexpr std::size_t kMagicSize = sizeof kMagic - 1;
constexpr std::size_t kDigestSize = 32;
constexpr std::size_t kHeaderSize = kMagicSize + sizeof(std::uint32_t) + sizeof(std::uint64_t);
// Fields are read from a checked payload, but a corrupt one with a valid
// checksum can only come from a bug or a forgery: lengths are still bounded.
constexpr std::uint64_t kMaxFieldBytes = std::uint64_t{1} << 40;

template <class T>
void append(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}


std::string describe_kind(int kind) {
  switch (kind) {
    case 0: return "numbers";
    case 1: return "integers";
    default: return "bytes";
  }
}

template <class T>
std::vector<T> unpack(const std::string& data, std::uint64_t count) {
  std::vector<T> values(count);
  if (count) std::memcpy(values.data(), data.data(), count * sizeof(T));
  return values;
}

}  // namespace

void CheckpointFields::put(const std::string& name, const std::vector<double>& values) {
  fields_[name] = {kF64, values.size(),
                   std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double))};
}

void CheckpointFields::put(const std::string& name, const std::vector<long long>& values) {
  fields_[name] = {kI64, values.size(),
                   std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(long long))};
}

void CheckpointFields::put(const std::string& name, const std::vector<int>& values) {
  put(name, std::vector<long long>(values.begin(), values.end()));
}

void CheckpointFields::put_text(const std::string& name, const std::string& text) {
  fields_[name] = {kBytes, text.size(), text};
}

void CheckpointFields::put_bytes(const std::string& name, const void* data, std::size_t size) {
  fields_[name] = {kBytes, size, size > 0 ? std::string(static_cast<const char*>(data), size) : std::string()};
}

const CheckpointFields::Field& CheckpointFields::field(const std::string& name, Kind kind) const {
  const auto it = fields_.find(name);
  if (it == fields_.end()) throw CheckpointError("it has no field '" + name + "'");
  if (it->second.kind != kind)
    throw CheckpointError("its field '" + name + "' holds " + describe_kind(it->second.kind) + ", expected " +
                          describe_kind(kind));
  return it->second;
}

namespace {
void check_count(const std::string& name, std::uint64_t count, long long expected) {
  if (expected >= 0 && count != static_cast<std::uint64_t>(expected))
    throw CheckpointError("its field '" + name + "' has " + std::to_string(count) + " values, the scene needs " +
                          std::to_string(expected));
}
}  // namespace

std::vector<double> CheckpointFields::numbers(const std::string& name, long long expected) const {
  const Field& f = field(name, kF64);
  check_count(name, f.count, expected);
  return unpack<double>(f.data, f.count);
}

std::vector<long long> CheckpointFields::integers(const std::string& name, long long expected) const {
  const Field& f = field(name, kI64);
  check_count(name, f.count, expected);
  return unpack<long long>(f.data, f.count);
}

std::vector<int> CheckpointFields::ints(const std::string& name, long long expected) const {
  const auto wide = integers(name, expected);
  return std::vector<int>(wide.begin(), wide.end());
}

std::string CheckpointFields::text(const std::string& name) const { return field(name, kBytes).data; }

void CheckpointFields::copy_from(const CheckpointFields& other, const std::string& name) {
  const auto it = other.fields_.find(name);
  if (it == other.fields_.end()) throw CheckpointError("it has no field '" + name + "'");
  fields_[name] = it->second;
}

std::vector<std::string> CheckpointFields::names_starting(const std::string& prefix) const {
  std::vector<std::string> names;
  for (auto it = fields_.lower_bound(prefix); it != fields_.end() && it->first.compare(0, prefix.size(), prefix) == 0; ++it)
    names.push_back(it->first);
  return names;
}

void CheckpointFields::bytes(const std::string& name, void* data, std::size_t size) const {
  const Field& f = field(name, kBytes);
  check_count(name, f.count, static_cast<long long>(size));
  if (size > 0) std::memcpy(data, f.data.data(), size);  // (data may be null when size is 0)
}

std::uint64_t CheckpointFields::payload_size() const {
  std::uint64_t size = sizeof(std::uint32_t);
  for (const auto& [name, f] : fields_)
    size += sizeof(std::uint16_t) + name.size() + sizeof(std::uint8_t) + sizeof f.count + f.data.size();
  return size;
}

std::uint64_t CheckpointFields::encoded_size() const {
  return kMagicSize + sizeof kCheckpointFormat + sizeof(std::uint64_t) + payload_size() + kDigestSize;
}

void CheckpointFields::encode_into(const std::function<void(std::string_view)>& write) const {
  Sha256 hash;
  auto put = [&](std::string_view piece) {
    hash.update(piece);
    write(piece);
  };
  std::string head(kMagic, kMagicSize);
  append(head, kCheckpointFormat);
  append(head, payload_size());
  append(head, static_cast<std::uint32_t>(fields_.size()));
  put(head);
  for (const auto& [name, f] : fields_) {
    head.clear();
    append(head, static_cast<std::uint16_t>(name.size()));
    head += name;
    append(head, static_cast<std::uint8_t>(f.kind));
    append(head, f.count);
    put(head);
    put(f.data);
  }
  const auto digest = hash.digest();
  write(std::string_view(reinterpret_cast<const char*>(digest.data()), digest.size()));
}

std::string CheckpointFields::encode() const {
  std::string out;
  encode_into([&](std::string_view piece) { out += piece; });
  return out;
}

namespace {

// Bytes in memory, taken in order (a header, a payload).
class BytesView {
 public:
  explicit BytesView(std::string_view bytes) : bytes_(bytes) {}
  std::size_t left() const { return bytes_.size() - at_; }
  void read(void* to, std::size_t n) {
    std::memcpy(to, bytes_.data() + at_, n);
    at_ += n;
  }

 private:
  std::string_view bytes_;
  std::size_t at_ = 0;
};

// A value of T from the payload.
template <class T, class Source>
T take_from(Source& source) {
  if (source.left() < sizeof(T)) throw CheckpointError("the payload ends inside a field");
  T value;
  source.read(&value, sizeof value);
  return value;
}

// The header (magic, format, payload length) of a file of file_size bytes,
// checked; returns the payload's length.
std::uint64_t check_header(std::string_view header, std::size_t file_size) {
  if (file_size < kHeaderSize + kDigestSize)
    throw CheckpointError("it is truncated (" + std::to_string(file_size) + " bytes, shorter than a header)");
  if (header.compare(0, kMagicSize, std::string_view(kMagic, kMagicSize)) != 0)
    throw CheckpointError("it is not a fibrodem checkpoint");
  BytesView rest(header.substr(kMagicSize));
  const auto format = take_from<std::uint32_t>(rest);
  if (format != kCheckpointFormat)
    throw CheckpointError("its format is " + std::to_string(format) + ", this fibrodem reads format " +
                          std::to_string(kCheckpointFormat));
  const auto length = take_from<std::uint64_t>(rest);
  if (length != file_size - kHeaderSize - kDigestSize)
    throw CheckpointError("it is truncated or has trailing bytes (payload of " + std::to_string(length) +
                          " bytes announced, " + std::to_string(file_size - kHeaderSize - kDigestSize) + " present)");
  return length;
}

const CheckpointError kChecksumMismatch("its checksum does not match its contents (the file is corrupt)");

}  // namespace

template <class Source>
CheckpointFields CheckpointFields::parse_payload(Source& source) {
  CheckpointFields fields;
  const auto count = take_from<std::uint32_t>(source);
  for (std::uint32_t i = 0; i < count; ++i) {
    const auto name_size = take_from<std::uint16_t>(source);
    if (source.left() < name_size) throw CheckpointError("the payload ends inside a field's name");
    std::string name(name_size, '\0');
    source.read(name.data(), name_size);
    const auto kind = take_from<std::uint8_t>(source);
    if (kind > kBytes) throw CheckpointError("field '" + name + "' is of unknown kind " + std::to_string(kind));
    const auto n = take_from<std::uint64_t>(source);
    const std::uint64_t width = kind == kBytes ? 1 : 8;
    if (n > kMaxFieldBytes / width || source.left() < n * width)
      throw CheckpointError("field '" + name + "' is longer than the payload");
    std::string data(n * width, '\0');
    source.read(data.data(), data.size());
    fields.fields_[name] = {static_cast<Kind>(kind), n, std::move(data)};
  }
  if (source.left() != 0) throw CheckpointError("the payload has bytes after its last field");
  return fields;
}

CheckpointFields CheckpointFields::decode(std::string_view in) {
  const std::uint64_t length = check_header(in.substr(0, std::min(in.size(), kHeaderSize)), in.size());
  const auto digest = sha256(in.substr(0, in.size() - kDigestSize));
  if (std::memcmp(digest.data(), in.data() + in.size() - kDigestSize, kDigestSize) != 0) throw kChecksumMismatch;
  BytesView payload(in.substr(kHeaderSize, length));
  return parse_payload(payload);
}

namespace {

[[noreturn]] void fail_writing(const std::filesystem::path& file, const std::string& what) {
  throw std::runtime_error("cannot write checkpoint " + file.string() + ": " + what + " (" + std::strerror(errno) +
                           ")");
}

void write_all(int fd, const char* data, std::size_t size, const std::filesystem::path& file) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail_writing(file, "write failed (is the disk full?)");
    data += n;
    size -= static_cast<std::size_t>(n);
  }
}

}  // namespace

void write_checkpoint_file(const std::filesystem::path& file, const CheckpointFields& fields,
                           const std::function<void()>& midway) {
  const std::filesystem::path temporary = file.string() + ".tmp";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail_writing(temporary, "cannot create it");
  try {
    const std::uint64_t half = fields.encoded_size() / 2;
    std::uint64_t written = 0;
    bool called = !midway;
    fields.encode_into([&](std::string_view piece) {
      if (!called && written + piece.size() >= half) {
        const auto first = static_cast<std::size_t>(half - written);
        write_all(fd, piece.data(), first, temporary);
        midway();
        called = true;
        piece.remove_prefix(first);
        written += first;
      }
      write_all(fd, piece.data(), piece.size(), temporary);
      written += piece.size();
    });
    if (::fsync(fd) != 0) fail_writing(temporary, "fsync failed");
  } catch (...) {
    ::close(fd);
    std::filesystem::remove(temporary);
    throw;
  }
  if (::close(fd) != 0) fail_writing(temporary, "close failed");
  if (std::rename(temporary.c_str(), file.c_str()) != 0) fail_writing(file, "rename failed");
  // The rename itself reaches the disk with the directory's own fsync.
  const int dir = ::open(file.parent_path().empty() ? "." : file.parent_path().c_str(), O_RDONLY | O_DIRECTORY);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
}

namespace {

// A payload read from the file as it is parsed, each piece added to the
// file's checksum: each field's data goes straight into its own storage,
// so reading a checkpoint holds it once (read whole first, then copied
// out, it would be held twice).
class PayloadFile {
 public:
  PayloadFile(std::ifstream& in, std::uint64_t length, Sha256& hash) : in_(in), left_(length), hash_(hash) {}
  std::size_t left() const { return static_cast<std::size_t>(left_); }
  void read(void* to, std::size_t n) {
    if (!in_.read(static_cast<char*>(to), static_cast<std::streamsize>(n)))
      throw CheckpointError("it cannot be read to its end");
    hash_.update(std::string_view(static_cast<const char*>(to), n));
    left_ -= n;
  }
  // The rest of the payload, into the checksum only.
  void skip_rest() {
    std::string chunk;
    while (left_ > 0) {
      chunk.resize(static_cast<std::size_t>(std::min<std::uint64_t>(left_, 1 << 20)));
      read(chunk.data(), chunk.size());
    }
  }

 private:
  std::ifstream& in_;
  std::uint64_t left_;
  Sha256& hash_;
};

// As decode() of the file's bytes, the same errors in the same order: a
// payload that does not parse is reported as corrupt when its checksum
// does not match either.
CheckpointFields read_checkpoint_stream(std::ifstream& in, std::size_t file_size) {
  std::string header(static_cast<std::size_t>(std::min<std::size_t>(file_size, kHeaderSize)), '\0');
  if (!in.read(header.data(), static_cast<std::streamsize>(header.size())))
    throw CheckpointError("it cannot be read");
  const std::uint64_t length = check_header(header, file_size);
  Sha256 hash;
  hash.update(header);
  PayloadFile payload(in, length, hash);
  const auto checksum_matches = [&] {
    std::array<char, kDigestSize> stored{};
    if (!in.read(stored.data(), kDigestSize)) throw CheckpointError("it cannot be read to its end");
    const auto digest = hash.digest();
    return std::memcmp(digest.data(), stored.data(), kDigestSize) == 0;
  };
  CheckpointFields fields;
  try {
    fields = CheckpointFields::parse_payload(payload);
  } catch (const CheckpointError&) {
    payload.skip_rest();
    if (!checksum_matches()) throw kChecksumMismatch;
    throw;
  }
  if (!checksum_matches()) throw kChecksumMismatch;
  return fields;
}

}  // namespace

CheckpointFields read_checkpoint_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) throw CheckpointError("checkpoint " + file.string() + " cannot be read");
  const auto file_size = static_cast<std::size_t>(in.tellg());
  in.seekg(0);
  try {
    return read_checkpoint_stream(in, file_size);
  } catch (const CheckpointError& e) {
    throw CheckpointError("checkpoint " + file.string() + ": " + e.what());
  }
}

}  // namespace fibrodem
