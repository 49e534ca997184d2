// The strings of the runtime's typed output (springbones/boundary.h), as the page reads them.
#pragma once

#include <string>
#include <string_view>

#include "common/typed_value.h"
#include "common/utf8_sequence.h"

namespace springbones {

/// Writes `v` as a string for the page: each byte that is not part of well-formed UTF-8 becomes
/// U+FFFD, as the JSON text of before showed it (a name cut inside a character). 0xFF, which is
/// no UTF-8 byte and starts a message number's placeholder (common/message_number.h), passes.
inline void pageText(TypedWriter& out, std::string_view v) {
  std::string shown;
  shown.reserve(v.size());
  for (std::size_t i = 0; i < v.size();) {
    const std::size_t length = utf8SequenceLength(v, i);
    if (length == 0 && static_cast<unsigned char>(v[i]) != 0xFF) {
      shown += "\xEF\xBF\xBD";  // U+FFFD
      ++i;
    } else {
      const std::size_t kept = length == 0 ? 1 : length;
      shown.append(v.data() + i, kept);
      i += kept;
    }
  }
  out.string(shown);
}

/// Writes {code, message, path}, the shape of a failure and of a warning, for the page.
inline void pageCodeMessagePath(TypedWriter& out, std::string_view code, std::string_view message,
                                std::string_view path) {
  out.object(3);
  out.key("code");
  pageText(out, code);
  out.key("message");
  pageText(out, message);
  out.key("path");
  pageText(out, path);
}

}  // namespace springbones
