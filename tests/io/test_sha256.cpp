/// SHA-256 of bytes and files against the FIPS 180-2 example digests.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "io/sha256.hpp"
#include "support/files.hpp"

namespace conserve::io {
namespace {

const std::string kAbc = "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
const std::string kEmpty = "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855";

TEST(Sha256, KnownDigests) {
  EXPECT_EQ(sha256_hex("abc"), kAbc);
  EXPECT_EQ(sha256_hex(""), kEmpty);
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Sha256, FileOfManyBlocksEqualsItsBytes) {
  const auto dir = test::scratch("sha256");
  std::string bytes;
  for (int i = 0; i < 200000; ++i) bytes += static_cast<char>(i * 7 % 256);  // several read buffers
  test::write_file(dir / "f.bin", bytes);
  EXPECT_EQ(file_sha256(dir / "f.bin"), sha256_hex(bytes));
  test::write_file(dir / "abc.txt", "abc");
  EXPECT_EQ(file_sha256(dir / "abc.txt"), kAbc);
  EXPECT_THROW(file_sha256(dir / "missing"), InputError);
}

}  // namespace
}  // namespace conserve::io
