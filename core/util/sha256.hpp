// SHA-256 (FIPS 180-4) of bytes: plugin files (summary.json), checkpoint files
// (their checksum), the settle cache's keys.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <string_view>

struct sha256_ctx;  // Nettle's (util/sha256.cpp)

namespace fibrodem {

std::array<unsigned char, 32> sha256(std::string_view bytes);
std::string sha256_hex(std::string_view bytes);  // 64 lowercase hex digits

// The digest of bytes given piece by piece (a checkpoint streamed to its file).
class Sha256 {
 public:
  Sha256();
  ~Sha256();
  void update(std::string_view bytes);
  std::array<unsigned char, 32> digest();  // of everything so far; starts afresh

 private:
  std::unique_ptr<::sha256_ctx> context_;
};

}  // namespace fibrodem
