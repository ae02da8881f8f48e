// SHA-256 against the examples of FIPS 180-4 (NIST's test vectors: "abc", the two-block message
// and a million 'a's, fed in pieces that straddle the 64-byte blocks) and against sha256sum.
#include "core/base/sha256.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "tests/support/cli_runner.h"

namespace momenta {
namespace {

TEST(Sha256Test, StandardExamples) {
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  // 55, 56 and 64 bytes: the padding fits, just does not fit, and needs a block of its own.
  EXPECT_EQ(Sha256Hex(std::string(55, 'a')),
            "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318");
  EXPECT_EQ(Sha256Hex(std::string(56, 'a')),
            "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a");
  EXPECT_EQ(Sha256Hex(std::string(64, 'a')),
            "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb");
}

TEST(Sha256Test, MillionAsInPieces) {
  Sha256 h;
  const std::string piece(1001, 'a');
  for (int k = 0; k < 1000; ++k) h.Update(piece.data(), k % 2 ? 999 : 1001);
  EXPECT_EQ(h.HexDigest(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256Test, AgreesWithSha256sum) {
  if (std::system("command -v sha256sum >/dev/null 2>&1") != 0) GTEST_SKIP() << "no sha256sum";
  testing::TempDir dir;
  std::string bytes;
  for (int k = 0; k < 100000; ++k) bytes += static_cast<char>((k * 2654435761u) >> 13);
  const std::string file = dir.Write("data", bytes);
  ASSERT_EQ(std::system(("sha256sum " + file + " > " + dir.File("sum")).c_str()), 0);
  EXPECT_EQ(testing::ReadText(dir.File("sum")).substr(0, 64), Sha256Hex(bytes));
}

}  // namespace
}  // namespace momenta
