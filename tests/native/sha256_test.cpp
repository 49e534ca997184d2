// SHA-256 against the FIPS 180-4 examples (NIST CSRC "SHA256.pdf" and the long-message test).
#include "content_hash/sha256.h"
#include "test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace springbones {
namespace {

using test::toHex;

std::string sha256Hex(const std::string& text) {
  return toHex(sha256(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

TEST(Sha256, HashesTheEmptyMessage) {
  EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST(Sha256, AcceptsNullDataWithSizeZero) {
  EXPECT_EQ(toHex(sha256(nullptr, 0)), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST(Sha256, HashesAbc) {
  EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(Sha256, Hashes448BitMessageThatNeedsAnExtraPaddingBlock) {
  // 56 bytes: the 0x80 byte and the 8-byte length no longer fit, so padding spills into block 2.
  EXPECT_EQ(sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Sha256, Hashes896BitMessage) {
  EXPECT_EQ(sha256Hex("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmno"
                      "ijklmnopjklmnopqklmnopqrlmnopqrsmnopqrstnopqrstu"),
            "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
}

TEST(Sha256, HashesOneMillionLetterA) {
  EXPECT_EQ(sha256Hex(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, PadsCorrectlyAroundTheBlockBoundary) {
  // Expected values from coreutils: head -c N /dev/zero | tr '\0' a | sha256sum
  EXPECT_EQ(sha256Hex(std::string(55, 'a')), "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318");
  EXPECT_EQ(sha256Hex(std::string(56, 'a')), "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a");
  EXPECT_EQ(sha256Hex(std::string(63, 'a')), "7d3e74a05d7db15bce4ad9ec0658ea98e3f06eeecf16b4c6fff2da457ddc2f34");
  EXPECT_EQ(sha256Hex(std::string(64, 'a')), "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb");
}

TEST(Sha256, IncrementalUpdatesInAnySplitEqualTheOneShotDigest) {
  std::vector<std::uint8_t> message(1000);
  for (std::size_t i = 0; i < message.size(); ++i) message[i] = static_cast<std::uint8_t>(i * 7 + 3);
  const Sha256Digest expected = sha256(message.data(), message.size());

  // Piece sizes that cross block boundaries at every offset, with empty updates mixed in.
  for (std::size_t piece : {1u, 3u, 63u, 64u, 65u, 127u, 200u}) {
    Sha256 hasher;
    for (std::size_t offset = 0; offset < message.size(); offset += piece) {
      const std::size_t take = std::min(piece, message.size() - offset);
      hasher.update(message.data() + offset, take);
      hasher.update(nullptr, 0);
    }
    EXPECT_EQ(hasher.final(), expected) << "piece size " << piece;
  }
}

TEST(Sha256, FinalStartsANewMessage) {
  Sha256 hasher;
  const std::string abc = "abc";
  hasher.update(reinterpret_cast<const std::uint8_t*>(abc.data()), abc.size());
  hasher.final();
  EXPECT_EQ(toHex(hasher.final()), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST(Sha256, InitDiscardsBytesAlreadyHashed) {
  Sha256 hasher;
  const std::string junk = "junk";
  hasher.update(reinterpret_cast<const std::uint8_t*>(junk.data()), junk.size());
  hasher.init();
  const std::string abc = "abc";
  hasher.update(reinterpret_cast<const std::uint8_t*>(abc.data()), abc.size());
  EXPECT_EQ(toHex(hasher.final()), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

}  // namespace
}  // namespace springbones
