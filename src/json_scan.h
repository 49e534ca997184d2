// A forward-only JSON scanner for the load fast paths (glb_loader.cpp, metadata.cpp).
//
// Why not nlohmann: building its DOM for a 7,000-node glTF (and again for the metadata) cost
// tens of milliseconds natively and far more in WebAssembly, where every call that may throw
// from a frame with destructors goes through a JavaScript trampoline, and musl's strtod and
// printf run on software long doubles. This scanner allocates nothing itself, never throws and
// never recurses, and reads the common number forms without strtod.
//
// It is a fast path, not a second parser with its own opinions: every method returns false when
// the input is anything it does not handle exactly as nlohmann-json 3.11 would (bad syntax, but
// also a byte order mark, nesting deeper than kMaxDepth, numbers beyond its exact range...). The
// caller then reruns the nlohmann-based reader, which produces the real result or the exact error
// message. So a `true` from here must mean "nlohmann accepts this and reads the same value":
//   - strings: UTF-8 validated with nlohmann's table (RFC 3629), control characters refused,
//     escapes decoded the same way (\uXXXX surrogate pairs combined, lone surrogates refused);
//   - numbers: RFC 8259 grammar; an integer token is read as nlohmann reads it (int64/uint64,
//     converted to double on demand, so "-0" is +0.0), any other token as the correctly rounded
//     double strtod would return (Clinger's exact fast path, else strtod itself).
#pragma once

#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "float_text.h"
#include "springbones.h"
#include "utf8_append.h"

namespace springbones {

/// loadSkeleton and parseSpringBonesText without their fast readers: the nlohmann-based path
/// alone. For the tests that check both readers give the same result on the same input.
Error loadSkeletonChecked(const std::uint8_t* data, std::size_t size, Skeleton& out);
Error parseSpringBonesTextChecked(const std::string& text, const std::string& hash, ModelEntry& out,
                                  std::vector<Warning>& warnings);
/// parseSpringBonesText over text the caller holds (the bindings read it in place from WASM
/// memory: copying half a megabyte into a std::string cost a tenth of the load).
Error parseSpringBonesTextView(std::string_view text, const std::string& hash, ModelEntry& out,
                               std::vector<Warning>& warnings);
/// The entries of springBones.models[hash] as web/springbones.js hands them over when the caller
/// gave an object (encodeEntries there) instead of JSON text, sparing JSON.stringify and the
/// parse. Layout, little-endian (the JS writes typed arrays): a header of 4 u32 (entry count,
/// bytes of the names, bytes of the centers, 0), then 6 doubles per entry (stiffness,
/// gravityPower, drag, gravityDir x y z; 8-aligned after the header), then per entry the end of
/// its name in the names, the end of its center in the centers (both u32, cumulative), its flags
/// (u32, kEntry*), then the UTF-8 names and the UTF-8 centers, each section back to back.
/// Accepts exactly what the fast text reader accepts (every value present readable and in range,
/// every name and center well-formed UTF-8, no repeated name) and gives the same entries and
/// warnings; false otherwise, including for any
/// inconsistent layout, with `out` empty and no warning added: the caller then goes through the
/// text, which gives the real warnings or error.
inline constexpr std::uint32_t kEntryStiffness = 1, kEntryGravityPower = 2, kEntryGravityDir = 4, kEntryDrag = 8,
                               kEntryCenter = 16,      ///< the entry has "center" (null or a name)
                               kEntryCenterName = 32,  ///< ... and it is a name (its bytes in the centers)
                               kEntryIsRoot = 64;      ///< isRoot is true (false and null read the same)
inline constexpr std::size_t kEntriesHeaderBytes = 16, kEntryBytes = 48 + 3 * 4;
bool readSpringBonesEntries(const std::uint8_t* data, std::size_t size, const std::string& hash, ModelEntry& out,
                            std::vector<Warning>& warnings);
/// Whether the fast readers take an input themselves (true) or leave it to the nlohmann path.
/// For the same tests, to make sure the fast path is exercised.
bool fastGltfReaderAccepts(const std::uint8_t* data, std::size_t size);
bool fastSpringBonesReaderAccepts(const std::string& text, const std::string& hash);

/// key == literal, inline: at -Oz string_view's == against a C string is strlen plus an
/// out-of-line compare per call, and the fast readers compare every key they meet.
template <std::size_t N>
inline bool keyIs(std::string_view key, const char (&literal)[N]) {
  if (key.size() != N - 1) return false;
  // A loop of known length the compiler unrolls (memcmp of 12 bytes stayed a call in WebAssembly).
  for (std::size_t i = 0; i + 1 < N; ++i) {
    if (key[i] != literal[i]) return false;
  }
  return true;
}

namespace json_scan_detail {
// true for the bytes a string holds as they are: 0x20..0x7F except '"' and '\\'.
struct PlainBytes {
  bool table[256];
  constexpr PlainBytes() : table() {
    for (int c = 0x20; c < 0x80; ++c) table[c] = c != '"' && c != '\\';
  }
  constexpr bool operator[](unsigned char c) const { return table[c]; }
};
inline constexpr PlainBytes kPlainByte{};
}  // namespace json_scan_detail

struct JsonNumber {
  double value = 0;       ///< what nlohmann's get<double>() returns
  bool integer = false;   ///< the token is an integer nlohmann stores as int64 or uint64
  bool negative = false;  ///< integer < 0 (only meaningful with `integer`)
  std::uint64_t magnitude = 0;  ///< |integer value| (only meaningful with `integer`)
};

/// The length of the well-formed UTF-8 sequence (RFC 3629, nlohmann's lexer table) that starts with
/// a byte >= 0x80 at p, or 0 when it is malformed or runs past end.
inline int utf8SequenceLength(const char* p, const char* end) {
  const unsigned char c = static_cast<unsigned char>(*p);
  unsigned char lo = 0x80, hi = 0xBF;
  int continuation = 0;
  if (c >= 0xC2 && c <= 0xDF) {
    continuation = 1;
  } else if (c == 0xE0) {
    continuation = 2, lo = 0xA0;
  } else if ((c >= 0xE1 && c <= 0xEC) || c == 0xEE || c == 0xEF) {
    continuation = 2;
  } else if (c == 0xED) {
    continuation = 2, hi = 0x9F;
  } else if (c == 0xF0) {
    continuation = 3, lo = 0x90;
  } else if (c >= 0xF1 && c <= 0xF3) {
    continuation = 3;
  } else if (c == 0xF4) {
    continuation = 3, hi = 0x8F;
  } else {
    return 0;
  }
  if (end - p <= continuation) return 0;
  for (int i = 1; i <= continuation; ++i) {
    const unsigned char b = static_cast<unsigned char>(p[i]);
    if (b < lo || b > hi) return 0;
    lo = 0x80, hi = 0xBF;
  }
  return continuation + 1;
}

/// Whether bytes are well-formed UTF-8 (what a JSON string holds once read).
inline bool wellFormedUtf8(std::string_view bytes) {
  const char* p = bytes.data();
  const char* const end = p + bytes.size();
  while (p < end) {
    if (static_cast<unsigned char>(*p) < 0x80) {
      ++p;
      continue;
    }
    const int length = utf8SequenceLength(p, end);
    if (length == 0) return false;
    p += length;
  }
  return true;
}

class JsonScan {
 public:
  static constexpr int kMaxDepth = 512;  ///< deeper values are left to the nlohmann path

  JsonScan(const char* begin, const char* end) : p_(begin), end_(end) {}

  /// The next non-whitespace byte without consuming it, or 0 at the end of the input.
  char peek() {
    skipWhitespace();
    return p_ < end_ ? *p_ : '\0';
  }

  /// Consumes `c` (after whitespace) when it is next.
  bool consume(char c) {
    if (p_ < end_ && *p_ == c) {  // compact JSON, as exporters write it: no whitespace to skip
      ++p_;
      return true;
    }
    if (peek() != c) return false;
    ++p_;
    return true;
  }

  /// True when only whitespace is left, or whitespace and then a NUL byte: nlohmann's lexer ends
  /// the input at a NUL (GLB JSON chunks padded with zeros parse) and refuses anything else.
  bool atEnd() { return peek() == '\0'; }

  /// A string token. Without escapes `out` points into the input; with escapes it is decoded into
  /// `scratch` and points there.
  bool string(std::string_view& out, std::string& scratch) {
    if (!consume('"')) return false;
    const char* start = p_;
    bool escaped = false;
    while (true) {
      // Printable ASCII other than '"' and '\\', the bulk of every string, one test per byte.
      while (p_ < end_ && json_scan_detail::kPlainByte[static_cast<unsigned char>(*p_)]) ++p_;
      if (p_ >= end_) return false;
      const unsigned char c = static_cast<unsigned char>(*p_);
      if (c == '"') break;
      if (c == '\\') {
        escaped = true;
        if (++p_ >= end_) return false;
        if (*p_ == 'u') {
          if (end_ - p_ < 5) return false;
          p_ += 5;
        } else {
          ++p_;
        }
        continue;
      }
      if (c < 0x20) return false;
      if (c < 0x80) {
        ++p_;
        continue;
      }
      if (!utf8Sequence()) return false;
    }
    const char* stop = p_++;
    if (!escaped) {
      out = std::string_view(start, static_cast<std::size_t>(stop - start));
      return true;
    }
    if (!unescape(start, stop, scratch)) return false;
    out = scratch;
    return true;
  }

  /// A number token (see the header comment for how its value is read).
  bool number(JsonNumber& out) {
    skipWhitespace();
    const char* start = p_;
    const bool negative = p_ < end_ && *p_ == '-';
    if (negative) ++p_;
    if (p_ >= end_ || !isDigit(*p_)) return false;
    // The significant digits while 19 fit (10^19 - 1 < 2^64), and the power of ten they scale by.
    std::uint64_t digits = 0;
    int significant = 0;
    int exponent = 0;
    bool exact = true;  // no nonzero digit was dropped
    const auto add = [&](char c, bool fraction) {
      const unsigned d = static_cast<unsigned>(c - '0');
      if (significant == 0 && d == 0) {
        if (fraction) --exponent;  // a leading zero of the fraction shifts the digits after it
        return;
      }
      if (significant < 19) {
        digits = digits * 10 + d;
        ++significant;
        if (fraction) --exponent;
      } else {
        if (!fraction) ++exponent;
        if (d != 0) exact = false;
      }
    };
    if (*p_ == '0') {
      ++p_;  // a leading 0 stands alone ("01" is two tokens, which the caller refuses)
    } else {
      while (p_ < end_ && isDigit(*p_)) add(*p_++, false);
    }
    bool integer = true;
    if (p_ < end_ && *p_ == '.') {
      integer = false;
      ++p_;
      if (p_ >= end_ || !isDigit(*p_)) return false;
      while (p_ < end_ && isDigit(*p_)) add(*p_++, true);
    }
    if (p_ < end_ && (*p_ == 'e' || *p_ == 'E')) {
      integer = false;
      ++p_;
      bool exp_negative = false;
      if (p_ < end_ && (*p_ == '+' || *p_ == '-')) exp_negative = *p_++ == '-';
      if (p_ >= end_ || !isDigit(*p_)) return false;
      int e = 0;
      while (p_ < end_ && isDigit(*p_)) {
        if (e < 100000) e = e * 10 + (*p_ - '0');
        ++p_;
      }
      exponent += exp_negative ? -e : e;
    }
    out = JsonNumber{};
    if (integer) {
      // nlohmann reads it with strtoll / strtoull (so "-0" is the integer 0), and with strtod
      // when it fits neither; 19 digits always fit both.
      if (!exact || exponent != 0) return slowDouble(start, out);
      // Below -2^63 nlohmann falls back to a double: the same value, but not an integer.
      out.integer = !negative || digits <= (std::uint64_t(1) << 63);
      out.negative = negative && digits != 0;
      out.magnitude = digits;
      out.value = static_cast<double>(digits);
      if (out.negative) out.value = -out.value;
      return true;
    }
    if (digits == 0) {  // every digit zero: the exponent does not matter
      out.value = negative ? -0.0 : 0.0;
      return true;
    }
    // Clinger: an integer of at most 53 bits and a power of ten of at most 22 are exact doubles,
    // so one IEEE multiplication or division rounds correctly: the double strtod returns.
    static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                        1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                        1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    if (exact && digits <= (std::uint64_t(1) << 53) && exponent >= -22 && exponent <= 22) {
      const double d = static_cast<double>(digits);
      const double v = exponent < 0 ? d / kPow10[-exponent] : d * kPow10[exponent];
      out.value = negative ? -v : v;
      return true;
    }
    // Longer significands (JavaScript and Python print doubles with up to 17 digits): exact
    // integer arithmetic, still without strtod, whose long doubles are software in WebAssembly.
    double v = 0;
    if (exact && exactDecimal(digits, exponent, v)) {
      out.value = negative ? -v : v;
      return true;
    }
    return slowDouble(start, out);
  }

  /// digits * 10^q rounded to the nearest double, ties to even (what strtod returns), for a
  /// nonzero `digits` and q in [-27, 19]; false outside that range. With 5^27 < 2^64 and
  /// 10^19 < 2^64 every step is exact in 128 bits: for q >= 0 the product itself; for q < 0 the
  /// significand shifted to the top of 128 bits divided by 5^-q (the 2^q goes to the binary
  /// exponent), a quotient of at least 74 bits plus a sticky bit for the remainder.
  static bool exactDecimal(std::uint64_t digits, int q, double& out) {
    using float_text_detail::u128;
    if (digits == 0 || q < -27 || q > 19) return false;
    u128 m = 0;
    int e2 = 0;  // the value is (m + fraction) * 2^e2, sticky = fraction != 0
    bool sticky = false;
    if (q >= 0) {
      std::uint64_t pow10 = 1;
      for (int i = 0; i < q; ++i) pow10 *= 10;
      m = static_cast<u128>(digits) * pow10;
    } else {
      const int shift = 64 + __builtin_clzll(digits);  // the top bit of digits to bit 127
      const u128 numerator = static_cast<u128>(digits) << shift;
      const u128 divisor = float_text_detail::pow5(-q);
      m = numerator / divisor;
      sticky = numerator % divisor != 0;
      e2 = -shift + q;
    }
    const std::uint64_t high = static_cast<std::uint64_t>(m >> 64);
    const std::uint64_t low = static_cast<std::uint64_t>(m);
    const int bits = high != 0 ? 128 - __builtin_clzll(high) : 64 - __builtin_clzll(low);  // m != 0
    if (bits > 53) {
      const int drop = bits - 53;
      const u128 dropped = m & ((u128(1) << drop) - 1);
      const u128 half = u128(1) << (drop - 1);
      m >>= drop;
      e2 += drop;
      if (dropped > half || (dropped == half && (sticky || (m & 1) != 0))) ++m;
      if (m == (u128(1) << 53)) {
        m >>= 1;
        ++e2;
      }
    }
    // m < 2^53 and the value lies within [1e-27, 2^64 * 1e19]: a normal double, so the scaling
    // by a power of two is exact.
    out = std::ldexp(static_cast<double>(static_cast<std::uint64_t>(m)), e2);
    return true;
  }

  /// Skips one value of any kind, checking it as strictly as the methods above. Iterative.
  /// `scratch` receives decoded strings with escapes (no allocation per call otherwise).
  bool skipValue(std::string& scratch) {
    char stack[kMaxDepth];  // '{' or '[' per open container
    int depth = 0;
    while (true) {
      // One value.
      const char c = peek();
      if (c == '{' || c == '[') {
        if (depth == kMaxDepth) return false;
        ++p_;
        stack[depth++] = c;
        const char close = c == '{' ? '}' : ']';
        if (consume(close)) {
          --depth;
        } else {
          if (c == '{' && !key(scratch)) return false;
          continue;
        }
      } else if (!scalar(scratch)) {
        return false;
      }
      // After a value: close containers or move to the next member.
      while (true) {
        if (depth == 0) return true;
        const char open = stack[depth - 1];
        if (consume(',')) {
          if (open == '{' && !key(scratch)) return false;
          break;
        }
        if (!consume(open == '{' ? '}' : ']')) return false;
        --depth;
      }
    }
  }

  /// One of true, false, null (checked), a string or a number.
  bool scalar(std::string& scratch) {
    const char c = peek();
    if (c == '"') {
      std::string_view ignored;
      return string(ignored, scratch);
    }
    if (c == 't') return word("true");
    if (c == 'f') return word("false");
    if (c == 'n') return word("null");
    JsonNumber ignored;
    return number(ignored);
  }

  bool word(const char* w) {
    skipWhitespace();
    const std::size_t n = std::strlen(w);
    if (static_cast<std::size_t>(end_ - p_) < n || std::memcmp(p_, w, n) != 0) return false;
    p_ += n;
    return true;
  }

 private:
  static bool isDigit(char c) { return c >= '0' && c <= '9'; }


  void skipWhitespace() {
    while (p_ < end_ && (*p_ == ' ' || *p_ == '\n' || *p_ == '\r' || *p_ == '\t')) ++p_;
  }

  bool key(std::string& scratch) {
    std::string_view ignored;
    return string(ignored, scratch) && consume(':');
  }

  // A multi-byte UTF-8 sequence at p_, well formed by RFC 3629 (nlohmann's lexer table).
  bool utf8Sequence() {
    const int length = utf8SequenceLength(p_, end_);
    p_ += length;
    return length != 0;
  }

  static int hex4(const char* p) {
    int v = 0;
    for (int i = 0; i < 4; ++i) {
      const char c = p[i];
      v <<= 4;
      if (c >= '0' && c <= '9') {
        v |= c - '0';
      } else if (c >= 'a' && c <= 'f') {
        v |= c - 'a' + 10;
      } else if (c >= 'A' && c <= 'F') {
        v |= c - 'A' + 10;
      } else {
        return -1;
      }
    }
    return v;
  }

  // Decodes the body of a string whose bytes (other than escapes) were already validated.
  static bool unescape(const char* p, const char* stop, std::string& out) {
    out.clear();
    while (p < stop) {
      if (*p != '\\') {
        out += *p++;
        continue;
      }
      const char e = p[1];
      p += 2;
      switch (e) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          const int unit = hex4(p);
          if (unit < 0) return false;
          p += 4;
          std::uint32_t cp = static_cast<std::uint32_t>(unit);
          if (unit >= 0xDC00 && unit <= 0xDFFF) return false;  // lone low surrogate
          if (unit >= 0xD800 && unit <= 0xDBFF) {
            if (stop - p < 6 || p[0] != '\\' || p[1] != 'u') return false;
            const int low = hex4(p + 2);
            if (low < 0xDC00 || low > 0xDFFF) return false;
            p += 6;
            cp = 0x10000 + ((cp - 0xD800) << 10) + static_cast<std::uint32_t>(low - 0xDC00);
          }
          appendUtf8(out, cp);
          break;
        }
        default:
          return false;
      }
    }
    return true;
  }

  // strtod on a copy of the token (the input is not NUL-terminated): correct, only slower.
  bool slowDouble(const char* start, JsonNumber& out) {
    const std::size_t n = static_cast<std::size_t>(p_ - start);
    char buffer[64];
    if (n >= sizeof buffer) return false;  // such long tokens are left to the nlohmann path
    std::memcpy(buffer, start, n);
    buffer[n] = '\0';
    out = JsonNumber{};
    out.value = std::strtod(buffer, nullptr);
    return true;
  }

  const char* p_;
  const char* end_;
};

}  // namespace springbones
