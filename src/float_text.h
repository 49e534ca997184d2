// Float to JSON number text, "the shortest decimal of at least 6 significant digits that reads
// back as the same float": what the rig description (wasm/bindings.cpp) shows for each float, so
// 0.4f reads 0.4 in JavaScript and not 0.4000000059604645.
//
// The reference is printf's "%.{6..9}g" with strtof as the round-trip check (shortestFloatDouble
// below, kept as the fallback and the tests' oracle). In WebAssembly musl's printf and strtof run
// on software 128-bit long doubles, microseconds per call, tens of thousands of calls for a large
// rig; shortestFloatText computes the same decimal with exact integer arithmetic instead, for
// floats in [1e-7, 1e7) (and zero), where every intermediate fits 128 bits.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace springbones {

/// The reference: the double nearest the shortest "%.pg" text (p from 6 to 9) that strtof reads
/// back as `value`.
inline double shortestFloatDouble(float value) {
  char text[32];
  for (int precision = 6; precision <= 9; ++precision) {
    std::snprintf(text, sizeof text, "%.*g", precision, static_cast<double>(value));
    if (std::strtof(text, nullptr) == value) break;
  }
  return std::strtod(text, nullptr);
}

namespace float_text_detail {

using u128 = unsigned __int128;

// 5^n for n <= 27 (the largest power that fits 64 bits; shortest float text needs at most 5^16,
// the exact decimal reader of json_scan.h up to 5^27).
inline u128 pow5(int n) {
  static constexpr std::uint64_t kPow5[28] = {
      1ull, 5ull, 25ull, 125ull, 625ull, 3125ull, 15625ull, 78125ull, 390625ull, 1953125ull,
      9765625ull, 48828125ull, 244140625ull, 1220703125ull, 6103515625ull, 30517578125ull,
      152587890625ull, 762939453125ull, 3814697265625ull, 19073486328125ull, 95367431640625ull,
      476837158203125ull, 2384185791015625ull, 11920928955078125ull, 59604644775390625ull,
      298023223876953125ull, 1490116119384765625ull, 7450580596923828125ull};
  return kPow5[n];
}

// Sign of a * 2^ea - b * 10^q (a, b >= 0), exactly. Callers keep the operands small enough.
inline int compare(u128 a, int ea, u128 b, int q) {
  if (q >= 0) {
    b *= pow5(q);
  } else {
    a *= pow5(-q);
  }
  const int d = ea - q;  // now compare a * 2^d with b
  if (d >= 0) {
    a <<= d;
  } else {
    b <<= -d;
  }
  return a < b ? -1 : a > b ? 1 : 0;
}

}  // namespace float_text_detail

/// Writes an integer in decimal at `out` (room for 20 characters); returns the length.
inline int writeInteger(char* out, long long value) {
  char text[24];
  char* end = text + sizeof text;
  char* p = end;
  unsigned long long magnitude = value < 0 ? 0ull - static_cast<unsigned long long>(value)
                                           : static_cast<unsigned long long>(value);
  do {
    *--p = static_cast<char>('0' + magnitude % 10);
    magnitude /= 10;
  } while (magnitude != 0);
  if (value < 0) *--p = '-';
  const int length = static_cast<int>(end - p);
  for (int i = 0; i < length; ++i) out[i] = p[i];
  return length;
}

namespace float_text_detail {

// The shortest "%.pg" decimal (p from 6 to 9) that reads back as `value`, as digits * 10^q with
// no trailing zero digit, for a finite nonzero value with 1e-7 <= |value| < 1e7; false outside
// that range.
inline bool shortestDecimal(float value, std::uint64_t& digits_out, int& q_out) {
  const float magnitude = std::fabs(value);
  if (!(magnitude >= 1e-7f && magnitude < 1e7f)) return false;
  // value = m * 2^e exactly, 2^23 <= m < 2^24.
  int ex = 0;
  const double fraction = std::frexp(static_cast<double>(magnitude), &ex);
  const std::uint64_t m = static_cast<std::uint64_t>(std::ldexp(fraction, 24));
  const int e = ex - 24;
  // E = floor(log10(value)), checked exactly.
  int E = static_cast<int>(std::floor(std::log10(static_cast<double>(magnitude))));
  if (compare(m, e, 1, E) < 0) --E;
  if (compare(m, e, 1, E + 1) >= 0) ++E;
  const bool even = (m & 1) == 0;
  const bool power_of_two = m == (std::uint64_t(1) << 23);
  std::uint64_t pow10p = 100000;
  for (int p = 6; p <= 9; ++p) {
    pow10p *= 10;  // 10^p
    int q = E - p + 1;
    // N = value / 10^q rounded half to even, as printf rounds.
    u128 num = m, den = 1;
    if (q >= 0) {
      den *= pow5(q);
    } else {
      num *= pow5(-q);
    }
    if (e - q >= 0) {
      num <<= (e - q);
    } else {
      den <<= (q - e);
    }
    u128 n = num / den;
    const u128 rem = num % den;
    if (2 * rem > den || (2 * rem == den && (n & 1) != 0)) ++n;
    if (n == pow10p) {
      n /= 10;
      ++q;
    }
    // Does N * 10^q read back as value? It must lie strictly between the midpoints to the
    // neighbouring floats, or on one of them when m is even (ties round to even).
    const int hi = compare(2 * m + 1, e - 1, n, q);  // sign of (upper midpoint - N*10^q)
    const int lo = power_of_two ? compare(4 * m - 1, e - 2, n, q) : compare(2 * m - 1, e - 1, n, q);
    const bool below_hi = hi > 0 || (hi == 0 && even);
    const bool above_lo = lo < 0 || (lo == 0 && even);
    if (!(below_hi && above_lo)) continue;
    std::uint64_t digits = static_cast<std::uint64_t>(n);
    while (digits % 10 == 0) {
      digits /= 10;
      ++q;
    }
    digits_out = digits;
    q_out = q;
    return true;
  }
  return false;  // not reached: 9 digits always read back
}

}  // namespace float_text_detail

/// Writes the JSON text of the number shortestFloatDouble(value) returns (not necessarily the
/// same characters, the same number once parsed) at `out`, which has room for
/// kMaxFloatTextLength characters; returns the length. "null" for a non-finite value, as nlohmann
/// writes one.
inline constexpr int kMaxFloatTextLength = 32;
inline int writeShortestFloat(char* out, float value) {
  if (!std::isfinite(value)) {
    std::memcpy(out, "null", 4);
    return 4;
  }
  if (value == 0.0f) {
    if (std::signbit(value)) {
      out[0] = '-', out[1] = '0';
      return 2;
    }
    out[0] = '0';
    return 1;
  }
  std::uint64_t digits = 0;
  int q = 0;
  if (float_text_detail::shortestDecimal(value, digits, q)) {
    int length = 0;
    if (value < 0) out[length++] = '-';
    length += writeInteger(out + length, static_cast<long long>(digits));
    if (q != 0) {
      out[length++] = 'e';
      length += writeInteger(out + length, q);
    }
    return length;
  }
  const int length = std::snprintf(out, kMaxFloatTextLength, "%.17g", shortestFloatDouble(value));
  return length;
}

/// shortestFloatDouble(value) for a finite value, the number JSON.parse makes of
/// writeShortestFloat's text, without printf or strtod in the usual range: digits < 10^9 and
/// |q| <= 22 are exact doubles, so one IEEE multiplication or division rounds correctly (Clinger).
inline double shortestFloatValue(float value) {
  if (value == 0.0f) return static_cast<double>(value);  // keeps -0
  std::uint64_t digits = 0;
  int q = 0;
  if (float_text_detail::shortestDecimal(value, digits, q) && q >= -22 && q <= 22) {
    static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                        1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                        1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const double d = static_cast<double>(digits);
    const double v = q < 0 ? d / kPow10[-q] : d * kPow10[q];
    return value < 0 ? -v : v;
  }
  return shortestFloatDouble(value);
}

/// writeShortestFloat appended to a string.
inline void appendShortestFloat(std::string& out, float value) {
  char text[kMaxFloatTextLength];
  out.append(text, static_cast<std::size_t>(writeShortestFloat(text, value)));
}

}  // namespace springbones
