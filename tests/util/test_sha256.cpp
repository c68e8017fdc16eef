// SHA-256 against the examples of FIPS 180-2 Appendix B (NIST) and the digests
// of Python's hashlib for lengths around the 55/56/64-byte padding boundaries.
#include <doctest/doctest.h>

#include <array>
#include <string>
#include <string_view>
#include <utility>

#include "util/sha256.hpp"

using namespace fibrodem;

TEST_CASE("SHA-256 gives FIPS 180-2's example digests") {
  // FIPS 180-2, Appendix B.1 ("abc"), B.2 (448 bits), B.3 (a million 'a').
  CHECK(sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  CHECK(sha256_hex(std::string(1000000, 'a')) ==
        "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  // The empty message (NIST's SHA-256 short-message test vector, Len = 0).
  CHECK(sha256_hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST_CASE("SHA-256 pads messages of every length around a block's end") {
  // 'x' repeated n times: the length field fits the last block (55), only
  // the padding byte fits (56-63), a whole block (64), two blocks (119, 120,
  // 128). Digests from Python's hashlib: hashlib.sha256(b'x' * n).hexdigest().
  const std::pair<std::size_t, const char*> cases[] = {
      {1, "2d711642b726b04401627ca9fbac32f5c8530fb1903cc4db02258717921a4881"},
      {55, "d5e285683cd4efc02d021a5c62014694958901005d6f71e89e0989fac77e4072"},
      {56, "04c26261370ee7541549d16dee320c723e3fd14671e66a099afe0a377c16888e"},
      {63, "75220b47218278e656f2013bb8f0c455a25eaf01e86c64924e9d48d89776d6f2"},
      {64, "7ce100971f64e7001e8fe5a51973ecdfe1ced42befe7ee8d5fd6219506b5393c"},
      {65, "9537c5fdf120482f7d58d25e9ed583f52c02b4e304ea814db1633ad565aed7e9"},
      {119, "000b48d4edf0fa7bee3c6236ecd2785baa5db4eeb8bb54341b029e0d9fa5fb0c"},
      {120, "13f05a0b594787f5ecd315edc96141bd3243203d1b7d4f0836f37308b276ba98"},
      {128, "24da1b81d0b16df6428eee73c69fcb2a93c76bc6df706f0c6670fe6bfe800464"},
  };
  for (const auto& c : cases) {
    CAPTURE(c.first);
    CHECK(sha256_hex(std::string(c.first, 'x')) == c.second);
  }
}

TEST_CASE("SHA-256 fed piece by piece gives the digest of the whole") {
  // FIPS 180-2's B.2 message cut at every place, and a million 'a' in
  // pieces of 1,000 and 7 (not a divisor of a block): the digests above.
  const std::string b2 = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
  const std::array<unsigned char, 32> whole = sha256(b2);
  for (std::size_t cut = 0; cut <= b2.size(); ++cut) {
    Sha256 hash;
    hash.update(std::string_view(b2).substr(0, cut));
    hash.update(std::string_view(b2).substr(cut));
    CHECK(hash.digest() == whole);
  }
  const std::string a(1000000, 'a');
  for (std::size_t piece : {std::size_t{1000}, std::size_t{7}}) {
    Sha256 hash;
    for (std::size_t at = 0; at < a.size(); at += piece) hash.update(std::string_view(a).substr(at, piece));
    CHECK(hash.digest() == sha256(a));
  }
  Sha256 again;  // a digest starts the hash afresh
  again.update("x");
  (void)again.digest();
  again.update("abc");
  CHECK(again.digest() == sha256("abc"));
}
