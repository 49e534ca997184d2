// SHA-256 (FIPS 180-4), written for springbones so the content hash needs no third-party
// crypto library in either the native or the WebAssembly build.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace springbones {

using Sha256Digest = std::array<std::uint8_t, 32>;

// Incremental SHA-256: init(), any number of update() calls, then final().
// A fresh object is already initialised; final() re-initialises it, so it can be reused.
class Sha256 {
 public:
  static constexpr std::size_t kBlockSize = 64;   ///< bytes per compression block
  static constexpr std::size_t kDigestSize = 32;  ///< bytes in the digest

  Sha256() noexcept { init(); }

  // Starts a new message, dropping anything hashed so far.
  void init() noexcept;

  // Appends size bytes. data may be null only when size is 0.
  void update(const std::uint8_t* data, std::size_t size) noexcept;

  // Pads the message, returns its digest and starts a new message.
  Sha256Digest final() noexcept;

 private:
  void compress(const std::uint8_t* block) noexcept;

  std::array<std::uint32_t, 8> state_;
  std::array<std::uint8_t, kBlockSize> buffer_;  // a partial block waiting for more bytes
  std::size_t buffer_size_;
  std::uint64_t message_size_;  // bytes; FIPS 180-4 limits messages to 2^64 bits anyway
};

// One-shot digest of size bytes. data may be null only when size is 0.
Sha256Digest sha256(const std::uint8_t* data, std::size_t size) noexcept;

}  // namespace springbones
