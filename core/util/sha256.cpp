// SHA-256 (FIPS 180-4) from GNU Nettle: a small library (one shared object
// with no dependencies of its own) where OpenSSL's libcrypto cost every
// process ~3,400 symbol bindings at load and a provider set-up on the first
// digest, more than a single cell's whole start-up budget. Debian builds
// Nettle "fat": it picks the CPU's SHA instructions at run time.
#include "util/sha256.hpp"

#include <nettle/sha2.h>

#include <cstdint>

namespace fibrodem {

Sha256::Sha256() : context_(std::make_unique<::sha256_ctx>()) { sha256_init(context_.get()); }

Sha256::~Sha256() = default;

void Sha256::update(std::string_view bytes) {
  sha256_update(context_.get(), bytes.size(), reinterpret_cast<const std::uint8_t*>(bytes.data()));
}

std::array<unsigned char, 32> Sha256::digest() {
  std::array<unsigned char, 32> out{};
  sha256_digest(context_.get(), out.size(), out.data());  // (Nettle resets the context)
  return out;
}

std::array<unsigned char, 32> sha256(std::string_view bytes) {
  Sha256 hash;
  hash.update(bytes);
  return hash.digest();
}

std::string sha256_hex(std::string_view bytes) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(64);
  for (unsigned char b : sha256(bytes)) {
    hex += kHex[b >> 4];
    hex += kHex[b & 15];
  }
  return hex;
}

}  // namespace fibrodem
