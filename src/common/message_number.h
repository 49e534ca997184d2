// A number in a message, in one of the printf conversions the messages use, and a message part cut
// to a length. Native code, the readers and the creator tools write the digits here
// (message_number.cpp, snprintf). The runtime WebAssembly module carries no number formatting: it
// links wasm/message_number_placeholders.cpp instead, which leaves each number in the message as
// a placeholder that web/message_numbers.js writes with the same digits, so a message is still
// written once, here in C++, and reads the same in both builds (tests/wasm/message_numbers.test.mjs).
//
// A placeholder is bytes that never occur in UTF-8 text (every string of the runtime is UTF-8):
//   a number:  0xFF, the conversion ('g', 'f', or 't' for %f without trailing zeros), its
//              precision as two decimal digits, the double's bits as 16 hex digits, most
//              significant first (20 bytes);
//   a cut:     0xFF, 'c', the length as two decimal digits, the text, 0xFF, 'e'.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace springbones {

/// printf's conversions, with the precision the messages use.
enum class NumberStyle : char {
  kG6,         ///< %.6g
  kG7,         ///< %.7g: 1e+30 rather than 31 digits
  kG15,        ///< %.15g: a value quoted from the input, with the digits a person typed
  kFixed,      ///< %f, as std::to_string writes a float
  kFixedTrim,  ///< %f without trailing zeros (and without a point then left at the end)
};

/// Appends `value` in `style` (or, in the runtime module, its placeholder).
void appendNumber(std::string& message, double value, NumberStyle style);

inline std::string numberText(double value, NumberStyle style) {
  std::string text;
  appendNumber(text, value, style);
  return text;
}

/// The fewest bytes `text` (written with appendNumber) has once its numbers are written.
std::size_t writtenLengthAtLeast(std::string_view text);

/// Appends `text` whole when it has at most `max_bytes` bytes once written (max_bytes < 100);
/// otherwise its first max_bytes - 3 bytes and "...", each byte of a character the cut splits
/// becoming U+FFFD (the cut text is UTF-8 again).
void appendCut(std::string& out, std::string_view text, std::size_t max_bytes);

namespace message_number_detail {

/// The bytes of a UTF-8 character cut at the end of `text` (0 when the last one is whole).
inline std::size_t cutCharacterBytes(std::string_view text) {
  std::size_t trailing = 0;
  while (trailing < text.size() && trailing < 3 &&
         (static_cast<unsigned char>(text[text.size() - 1 - trailing]) & 0xC0) == 0x80) {
    ++trailing;
  }
  if (trailing == text.size()) return trailing;
  const unsigned char lead = static_cast<unsigned char>(text[text.size() - 1 - trailing]);
  const std::size_t length = lead < 0x80 ? 1 : lead >= 0xF0 ? 4 : lead >= 0xE0 ? 3 : lead >= 0xC0 ? 2 : 1;
  return length > trailing + 1 ? trailing + 1 : 0;
}

/// The cut of appendCut on text whose bytes are all written.
inline void appendCutBytes(std::string& out, std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) {
    out += text;
    return;
  }
  const std::string_view kept = text.substr(0, max_bytes - 3);
  const std::size_t cut = cutCharacterBytes(kept);
  out += kept.substr(0, kept.size() - cut);
  for (std::size_t i = 0; i < cut; ++i) out += "\xEF\xBF\xBD";  // U+FFFD
  out += "...";
}

}  // namespace message_number_detail
}  // namespace springbones
