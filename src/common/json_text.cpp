#include "common/json_text.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <type_traits>
#include <vector>

namespace springbones {
namespace {

// The decimal text %g wrote, read back as a float. Exact for what the loop below asks about (at
// most 9 significant digits, a power of ten within double's exact range): one correctly rounded
// double operation, then the float. Beyond that range it answers false and the caller keeps its
// 9 digits, which always read back. Ours rather than strtod, which would bring its long-double
// arithmetic into the runtime for this one use.
bool readsBackAs(const char* text, float v) {
  static const double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                  1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  const char* c = text;
  const bool negative = *c == '-';
  if (negative) ++c;
  std::uint64_t mantissa = 0;
  int exponent = 0;
  for (; *c >= '0' && *c <= '9'; ++c) mantissa = mantissa * 10 + std::uint64_t(*c - '0');
  if (*c == '.') {
    for (++c; *c >= '0' && *c <= '9'; ++c) {
      mantissa = mantissa * 10 + std::uint64_t(*c - '0');
      --exponent;
    }
  }
  if (*c == 'e') {
    ++c;
    const bool minus = *c == '-';
    if (*c == '-' || *c == '+') ++c;
    int e = 0;
    for (; *c >= '0' && *c <= '9'; ++c) e = e * 10 + (*c - '0');
    exponent += minus ? -e : e;
  }
  if (exponent < -22 || exponent > 22) return false;
  double value = double(mantissa);
  value = exponent >= 0 ? value * kPow10[exponent] : value / kPow10[-exponent];
  return static_cast<float>(negative ? -value : value) == v;
}

// The shortest %g text of a float that reads back as the same float.
void appendShortest(std::string& out, float v) {
  char buffer[32];
  for (int digits = 1; digits <= 9; ++digits) {
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, static_cast<double>(v));
    if (readsBackAs(buffer, v)) break;
  }
  out += buffer;
}

// A double with the digits a person typed (15 significant digits read back as what was written).
void appendDouble(std::string& out, double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.15g", v);
  out += buffer;
}

template <typename T>
void appendNumber(std::string& out, T v) {
  if (!std::isfinite(v)) {
    out += "null";
  } else if (v == std::trunc(v) && std::fabs(v) < 1e15) {
    out += std::to_string(static_cast<long long>(v));
  } else if constexpr (std::is_same_v<T, float>) {
    appendShortest(out, v);
  } else {
    appendDouble(out, v);
  }
}

// Length of the UTF-8 sequence starting at s[i], or 0 when it is not well-formed (overlong forms,
// surrogates and code points past U+10FFFF are not).
std::size_t utf8Sequence(std::string_view s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = byte(i);
  if (c < 0x80) return 1;
  std::size_t length = 0;
  unsigned lo = 0x80, hi = 0xBF;
  if (c >= 0xC2 && c <= 0xDF) {
    length = 2;
  } else if (c >= 0xE0 && c <= 0xEF) {
    length = 3;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    length = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (s.size() - i < length) return 0;
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < length; ++k) {
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  }
  return length;
}

void appendString(std::string& out, std::string_view s) {
  out += '"';
  for (std::size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20) {
      static const char* kHex = "0123456789abcdef";
      switch (c) {
        case '\n': out += "\\n"; break;
        case '\r': out += "\\r"; break;
        case '\t': out += "\\t"; break;
        case '\b': out += "\\b"; break;
        case '\f': out += "\\f"; break;
        default:
          out += "\\u00";
          out += kHex[c >> 4];
          out += kHex[c & 15];
      }
    } else if (c >= 0x80) {
      const std::size_t length = utf8Sequence(s, i);
      if (length == 0) {
        out += "\xEF\xBF\xBD";  // U+FFFD
        ++i;
        continue;
      }
      out.append(s.data() + i, length);
      i += length;
      continue;
    } else {
      out += static_cast<char>(c);
    }
    ++i;
  }
  out += '"';
}

}  // namespace

void JsonText::separate() {
  if (need_comma_) out_ += ',';
  need_comma_ = true;
}

JsonText& JsonText::beginObject() {
  separate();
  out_ += '{';
  need_comma_ = false;
  return *this;
}

JsonText& JsonText::endObject() {
  out_ += '}';
  need_comma_ = true;
  return *this;
}

JsonText& JsonText::beginArray() {
  separate();
  out_ += '[';
  need_comma_ = false;
  return *this;
}

JsonText& JsonText::endArray() {
  out_ += ']';
  need_comma_ = true;
  return *this;
}

JsonText& JsonText::key(std::string_view k) {
  separate();
  appendString(out_, k);
  out_ += ':';
  need_comma_ = false;
  return *this;
}

JsonText& JsonText::value(std::string_view v) {
  separate();
  appendString(out_, v);
  return *this;
}

JsonText& JsonText::value(float v) {
  separate();
  appendNumber(out_, v);
  return *this;
}

JsonText& JsonText::value(double v) {
  separate();
  appendNumber(out_, v);
  return *this;
}

JsonText& JsonText::value(long long v) {
  separate();
  out_ += std::to_string(v);
  return *this;
}

JsonText& JsonText::value(bool v) {
  separate();
  out_ += v ? "true" : "false";
  return *this;
}

JsonText& JsonText::null() {
  separate();
  out_ += "null";
  return *this;
}

JsonText& JsonText::vec3(float x, float y, float z) { return beginArray().value(x).value(y).value(z).endArray(); }

std::string quoteValue(const TypedValue& value, std::size_t max_chars) {
  // Depth-first with an explicit stack of (value, member key or none, first child?) entries.
  struct Item {
    TypedValue value;
    TypedValue::iterator next;
    TypedValue::iterator end;
    bool object;
  };
  std::string out;
  std::vector<Item> open;
  const auto scalar = [&](const TypedValue& v) {
    switch (v.type()) {
      case TypedValue::Type::kNull: out += "null"; break;
      case TypedValue::Type::kFalse: out += "false"; break;
      case TypedValue::Type::kTrue: out += "true"; break;
      case TypedValue::Type::kString: appendString(out, v.string()); break;
      case TypedValue::Type::kNumber: {
        const double n = v.number();
        // A message, not JSON: a non-finite number is named.
        if (std::isnan(n)) {
          out += "NaN";
        } else if (std::isinf(n)) {
          out += n > 0 ? "Infinity" : "-Infinity";
        } else {
          appendNumber(out, n);
        }
        break;
      }
      default: break;
    }
  };
  const auto enter = [&](const TypedValue& v) {
    if (!v.is_structured()) {
      scalar(v);
      return;
    }
    out += v.is_object() ? '{' : '[';
    open.push_back(Item{v, v.begin(), v.end(), v.is_object()});
  };
  enter(value);
  while (!open.empty() && out.size() <= max_chars) {
    Item& top = open.back();
    if (top.next == top.end) {
      out += top.object ? '}' : ']';
      open.pop_back();
      continue;
    }
    if (top.next != top.value.begin()) out += ',';
    if (top.object) {
      appendString(out, top.next.key());
      out += ':';
    }
    const TypedValue child = *top.next;
    ++top.next;
    enter(child);
  }
  if (out.size() > max_chars) out = out.substr(0, max_chars - 3) + "...";
  return out;
}

}  // namespace springbones
