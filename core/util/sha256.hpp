// SHA-256 (FIPS 180-4) of bytes: plugin files (summary.json), checkpoint files
// (their checksum), the settle cache's keys.
#pragma once

#include <array>
#include <string>
#include <string_view>

namespace fibrodem {

std::array<unsigned char, 32> sha256(std::string_view bytes);
std::string sha256_hex(std::string_view bytes);  // 64 lowercase hex digits

}  // namespace fibrodem
