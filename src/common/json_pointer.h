// JSON Pointer (RFC 6901) tokens for the paths our warnings and validation errors name.
#pragma once

#include <string>

namespace springbones {

/// "/" + key with '~' and '/' escaped, so paths stay unambiguous for names containing them. The
/// same form Ajv writes into instancePath, which the validator's messages must match.
inline std::string pointerToken(const std::string& key) {
  std::string out = "/";
  out.reserve(key.size() + 1);
  for (char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace springbones
