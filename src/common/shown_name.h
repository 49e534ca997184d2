// The one way a message quotes a name from the input (a node, a bone key, a file): at most
// kTypedMaxNameBytesInMessage bytes of it, cut at a UTF-8 boundary, then "...". A name is input, and
// copying all of it into each warning would make the warnings grow with the name times their
// number (typed_encoding.json, "maxNameBytesInMessage"; web/typed_value.js quotes the same).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "common/typed_encoding.h"

namespace springbones {

inline std::string shownName(std::string_view name) {
  if (name.size() <= kTypedMaxNameBytesInMessage) return std::string(name);
  std::size_t cut = kTypedMaxNameBytesInMessage;
  while (cut > 0 && (static_cast<unsigned char>(name[cut]) & 0xC0) == 0x80) --cut;  // not inside a UTF-8 sequence
  return std::string(name.substr(0, cut)) + "...";
}

}  // namespace springbones
