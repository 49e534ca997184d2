// SHA-256 as specified in FIPS 180-4, sections 4.1.2, 4.2.2, 5.1.1, 5.3.3 and 6.2.
// Plain portable C++ (no intrinsics) so the same code runs natively and in WebAssembly.
#include "content_hash/sha256.h"

#include <cstring>

namespace springbones {
namespace {

// FIPS 180-4 4.2.2: first 32 bits of the fractional parts of the cube roots of the first 64 primes.
constexpr std::uint32_t kRoundConstants[64] = {
    0x428a2f98u, 0x71374491u, 0xb5c0fbcfu, 0xe9b5dba5u, 0x3956c25bu, 0x59f111f1u, 0x923f82a4u, 0xab1c5ed5u,
    0xd807aa98u, 0x12835b01u, 0x243185beu, 0x550c7dc3u, 0x72be5d74u, 0x80deb1feu, 0x9bdc06a7u, 0xc19bf174u,
    0xe49b69c1u, 0xefbe4786u, 0x0fc19dc6u, 0x240ca1ccu, 0x2de92c6fu, 0x4a7484aau, 0x5cb0a9dcu, 0x76f988dau,
    0x983e5152u, 0xa831c66du, 0xb00327c8u, 0xbf597fc7u, 0xc6e00bf3u, 0xd5a79147u, 0x06ca6351u, 0x14292967u,
    0x27b70a85u, 0x2e1b2138u, 0x4d2c6dfcu, 0x53380d13u, 0x650a7354u, 0x766a0abbu, 0x81c2c92eu, 0x92722c85u,
    0xa2bfe8a1u, 0xa81a664bu, 0xc24b8b70u, 0xc76c51a3u, 0xd192e819u, 0xd6990624u, 0xf40e3585u, 0x106aa070u,
    0x19a4c116u, 0x1e376c08u, 0x2748774cu, 0x34b0bcb5u, 0x391c0cb3u, 0x4ed8aa4au, 0x5b9cca4fu, 0x682e6ff3u,
    0x748f82eeu, 0x78a5636fu, 0x84c87814u, 0x8cc70208u, 0x90befffau, 0xa4506cebu, 0xbef9a3f7u, 0xc67178f2u,
};

// FIPS 180-4 5.3.3: first 32 bits of the fractional parts of the square roots of the first 8 primes.
constexpr std::uint32_t kInitialState[8] = {
    0x6a09e667u, 0xbb67ae85u, 0x3c6ef372u, 0xa54ff53au, 0x510e527fu, 0x9b05688cu, 0x1f83d9abu, 0x5be0cd19u,
};

// Compilers turn this pattern into a single rotate instruction (and i32.rotr in WebAssembly).
inline std::uint32_t rotr(std::uint32_t x, unsigned n) { return (x >> n) | (x << (32u - n)); }

// SHA-256 reads words big-endian regardless of the host, so assemble them byte by byte.
inline std::uint32_t loadBigEndian32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
}

inline void storeBigEndian32(std::uint32_t value, std::uint8_t* p) {
  p[0] = static_cast<std::uint8_t>(value >> 24);
  p[1] = static_cast<std::uint8_t>(value >> 16);
  p[2] = static_cast<std::uint8_t>(value >> 8);
  p[3] = static_cast<std::uint8_t>(value);
}

}  // namespace

void Sha256::init() noexcept {
  std::memcpy(state_.data(), kInitialState, sizeof(kInitialState));
  buffer_size_ = 0;
  message_size_ = 0;
}

void Sha256::compress(const std::uint8_t* block) noexcept {
  // Message schedule (6.2.2 step 1), kept as a 16-word ring so it stays in registers/L1.
  std::uint32_t w[16];
  for (int t = 0; t < 16; ++t) w[t] = loadBigEndian32(block + 4 * t);

  std::uint32_t a = state_[0], b = state_[1], c = state_[2], d = state_[3];
  std::uint32_t e = state_[4], f = state_[5], g = state_[6], h = state_[7];

  for (int t = 0; t < 64; ++t) {
    std::uint32_t wt;
    if (t < 16) {
      wt = w[t];
    } else {
      const std::uint32_t w15 = w[(t - 15) & 15];
      const std::uint32_t w2 = w[(t - 2) & 15];
      const std::uint32_t sigma0 = rotr(w15, 7) ^ rotr(w15, 18) ^ (w15 >> 3);
      const std::uint32_t sigma1 = rotr(w2, 17) ^ rotr(w2, 19) ^ (w2 >> 10);
      wt = w[t & 15] + sigma0 + w[(t - 7) & 15] + sigma1;
      w[t & 15] = wt;
    }
    const std::uint32_t big_sigma1 = rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25);
    const std::uint32_t choose = (e & f) ^ (~e & g);
    const std::uint32_t t1 = h + big_sigma1 + choose + kRoundConstants[t] + wt;
    const std::uint32_t big_sigma0 = rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22);
    const std::uint32_t majority = (a & b) ^ (a & c) ^ (b & c);
    const std::uint32_t t2 = big_sigma0 + majority;
    h = g;
    g = f;
    f = e;
    e = d + t1;
    d = c;
    c = b;
    b = a;
    a = t1 + t2;
  }

  state_[0] += a;
  state_[1] += b;
  state_[2] += c;
  state_[3] += d;
  state_[4] += e;
  state_[5] += f;
  state_[6] += g;
  state_[7] += h;
}

void Sha256::update(const std::uint8_t* data, std::size_t size) noexcept {
  // memcpy with a null pointer is undefined even for 0 bytes, so leave before touching data.
  if (size == 0) return;
  message_size_ += size;

  if (buffer_size_ > 0) {
    const std::size_t take = (kBlockSize - buffer_size_ < size) ? kBlockSize - buffer_size_ : size;
    std::memcpy(buffer_.data() + buffer_size_, data, take);
    buffer_size_ += take;
    data += take;
    size -= take;
    if (buffer_size_ < kBlockSize) return;
    compress(buffer_.data());
    buffer_size_ = 0;
  }

  // Whole blocks straight from the caller's memory: no copy on the hot path.
  while (size >= kBlockSize) {
    compress(data);
    data += kBlockSize;
    size -= kBlockSize;
  }

  if (size > 0) {
    std::memcpy(buffer_.data(), data, size);
    buffer_size_ = size;
  }
}

Sha256Digest Sha256::final() noexcept {
  // 5.1.1: append bit '1', zeros up to 56 mod 64 bytes, then the length in bits (big-endian).
  const std::uint64_t message_bits = message_size_ * 8u;
  buffer_[buffer_size_++] = 0x80;
  if (buffer_size_ > kBlockSize - 8) {
    std::memset(buffer_.data() + buffer_size_, 0, kBlockSize - buffer_size_);
    compress(buffer_.data());
    buffer_size_ = 0;
  }
  std::memset(buffer_.data() + buffer_size_, 0, kBlockSize - 8 - buffer_size_);
  storeBigEndian32(static_cast<std::uint32_t>(message_bits >> 32), buffer_.data() + kBlockSize - 8);
  storeBigEndian32(static_cast<std::uint32_t>(message_bits), buffer_.data() + kBlockSize - 4);
  compress(buffer_.data());

  Sha256Digest digest;
  for (std::size_t i = 0; i < 8; ++i) storeBigEndian32(state_[i], digest.data() + 4 * i);
  init();
  return digest;
}

Sha256Digest sha256(const std::uint8_t* data, std::size_t size) noexcept {
  Sha256 hasher;
  hasher.update(data, size);
  return hasher.final();
}

}  // namespace springbones
