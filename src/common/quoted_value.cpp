#include "common/quoted_value.h"

#include <cmath>
#include <string_view>
#include <vector>

#include "common/message_number.h"
#include "common/utf8_sequence.h"

namespace springbones {
namespace {

// A string as JSON writes it, with U+FFFD for each byte that is not part of well-formed UTF-8.
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
      const std::size_t length = utf8SequenceLength(s, i);
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

void appendNumberValue(std::string& out, double n) {
  // A message, not JSON: a non-finite number is named.
  if (std::isnan(n)) {
    out += "NaN";
  } else if (std::isinf(n)) {
    out += n > 0 ? "Infinity" : "-Infinity";
  } else if (n == std::trunc(n) && std::fabs(n) < 1e15) {
    out += std::to_string(static_cast<long long>(n));
  } else {
    appendNumber(out, n, NumberStyle::kG15);
  }
}

}  // namespace

std::string quoteValue(const TypedValue& value, std::size_t max_chars) {
  // Depth-first with an explicit stack of (value, next child, end, object?) entries.
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
      case TypedValue::Type::kNumber: appendNumberValue(out, v.number()); break;
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
  while (!open.empty() && writtenLengthAtLeast(out) <= max_chars) {
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
  std::string quoted;
  appendCut(quoted, out, max_chars);
  return quoted;
}

}  // namespace springbones
