// JSON text out of the runtime (the rig description, errors, limits), written by hand: the runtime
// reads no JSON text and carries no JSON library, and what it writes is a few flat shapes.
// A float is written as the shortest text that reads back as the same float (0.4f as 0.4), a
// double with 15 significant digits (what a person typed reads back as typed), integers exactly,
// non-finite numbers as null, and strings that are not UTF-8 with U+FFFD in
// place of each bad byte, so JSON.parse on the JavaScript side always succeeds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "common/typed_value.h"

namespace springbones {

class JsonText {
 public:
  JsonText& beginObject();
  JsonText& endObject();
  JsonText& beginArray();
  JsonText& endArray();
  /// The next member's key (inside an object).
  JsonText& key(std::string_view k);
  JsonText& value(std::string_view v);
  JsonText& value(const char* v) { return value(std::string_view(v)); }
  JsonText& value(const std::string& v) { return value(std::string_view(v)); }
  JsonText& value(float v);
  JsonText& value(double v);
  JsonText& value(int v) { return value(static_cast<long long>(v)); }
  JsonText& value(long long v);
  JsonText& value(unsigned long v) { return value(static_cast<long long>(v)); }
  JsonText& value(unsigned long long v) { return value(static_cast<long long>(v)); }
  JsonText& value(unsigned v) { return value(static_cast<long long>(v)); }
  JsonText& value(bool v);
  JsonText& null();
  /// [x, y, z] of float components.
  JsonText& vec3(float x, float y, float z);
  const std::string& text() const { return out_; }
  std::string take() { return std::move(out_); }

 private:
  void separate();
  std::string out_;
  bool need_comma_ = false;
};

/// A typed value as compact JSON text (objects in key order), for messages that quote a bad value:
/// cut to at most `max_chars` (with "..." at the end) without walking the rest of a large value.
std::string quoteValue(const TypedValue& value, std::size_t max_chars);

}  // namespace springbones
