// The runtime module's message numbers (common/message_number.h): placeholders that
// web/message_numbers.js writes, so that the module links no number formatting (snprintf and its
// floating-point digits were 4.7 KB gzip of it). Linked into the runtime and crowd modules ahead
// of the runtime library, whose snprintf version (src/common/message_number.cpp) then stays out.
#include <cstdint>
#include <cstring>

#include "common/message_number.h"

namespace springbones {
namespace {

constexpr char kMark = '\xFF';

void appendTwoDigits(std::string& out, std::size_t n) {
  out += static_cast<char>('0' + n / 10 % 10);
  out += static_cast<char>('0' + n % 10);
}

}  // namespace

void appendNumber(std::string& message, double value, NumberStyle style) {
  char conversion = 'g';
  std::size_t precision = 6;
  switch (style) {
    case NumberStyle::kG6: break;
    case NumberStyle::kG7: precision = 7; break;
    case NumberStyle::kG15: precision = 15; break;
    case NumberStyle::kFixed: conversion = 'f'; break;
    case NumberStyle::kFixedTrim: conversion = 't'; break;
  }
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  message += kMark;
  message += conversion;
  appendTwoDigits(message, precision);
  for (int shift = 60; shift >= 0; shift -= 4) message += "0123456789abcdef"[(bits >> shift) & 15];
}

// A number's placeholder is 20 bytes and writes at least one.
std::size_t writtenLengthAtLeast(std::string_view text) {
  std::size_t numbers = 0;
  for (char c : text) numbers += c == kMark;
  return text.size() - 19 * numbers;
}

void appendCut(std::string& out, std::string_view text, std::size_t max_bytes) {
  if (text.find(kMark) == std::string_view::npos) {
    message_number_detail::appendCutBytes(out, text, max_bytes);
    return;
  }
  out += kMark;
  out += 'c';
  appendTwoDigits(out, max_bytes);
  out += text;
  out += kMark;
  out += 'e';
}

}  // namespace springbones
