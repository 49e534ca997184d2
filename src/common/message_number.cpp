// The numbers of messages written with snprintf: native code, the readers and the creator tools
// (the runtime module writes placeholders instead: wasm/message_number_placeholders.cpp).
#include <cstdio>

#include "common/message_number.h"

namespace springbones {

void appendNumber(std::string& message, double value, NumberStyle style) {
  char text[512];  // %f of the largest float is 46 characters, of the largest double 316
  switch (style) {
    case NumberStyle::kG6: std::snprintf(text, sizeof text, "%.6g", value); break;
    case NumberStyle::kG7: std::snprintf(text, sizeof text, "%.7g", value); break;
    case NumberStyle::kG15: std::snprintf(text, sizeof text, "%.15g", value); break;
    case NumberStyle::kFixed:
    case NumberStyle::kFixedTrim: std::snprintf(text, sizeof text, "%f", value); break;
  }
  std::string written(text);
  if (style == NumberStyle::kFixedTrim) {
    written.erase(written.find_last_not_of('0') + 1);
    if (!written.empty() && written.back() == '.') written.pop_back();
  }
  message += written;
}

std::size_t writtenLengthAtLeast(std::string_view text) { return text.size(); }

void appendCut(std::string& out, std::string_view text, std::size_t max_bytes) {
  message_number_detail::appendCutBytes(out, text, max_bytes);
}

}  // namespace springbones
