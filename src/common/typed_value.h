// A JSON value that arrives as typed data rather than text (docs/design.md, "Typed input"): what a
// page already parsed (three.js's glTF JSON, the entity the page read), written by
// web/typed_value.js, or what the readers parsed from bytes (src/readers/). The runtime's rules
// read every input through this view, so both front ends meet the same code.
//
// The encoding, little-endian, one value:
//   null | false | true: the tag alone
//   number: the tag, f64 (NaN and infinities allowed: a JS object can hold them)
//   float:  the tag, f32 (only in what the runtime writes for the page, TypedWriter::float32)
//   string: the tag, u32 byte length, UTF-8 bytes
//   array:  the tag, u32 count, then that many values
//   object: the tag, u32 count, then per member a u32 key length, the key's UTF-8 bytes and a value
// The tags and bounds are described once, in src/common/typed_encoding.json (typed_encoding.h and
// web/typed_encoding.js are generated from it).
// The view mimics the part of nlohmann::json's interface the readers use (is_*, size, find, end,
// operator[], get<T>, key()), and iterates an object's members in byte order of their keys, as
// nlohmann's std::map does, so warnings come out in one order whatever parsed the input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "common/typed_encoding.h"
#include "springbones/springbones.h"

namespace springbones {

class TypedDocument;

// The bounds of one typed input (typed_encoding.h: kTypedMaxStringBytes for a string or a key,
// kTypedMaxContainerSize for an array's elements or an object's members, kTypedMaxValues in all)
// are each checked before the work they bound. The whole input is bounded by its kind:
// kMaxGltfJsonBytes for a glTF document, kMaxMetadataBytes for springBones, an entity, options.

/// One value of a TypedDocument: a cheap handle, valid while the document lives.
class TypedValue {
 public:
  enum class Type : std::uint8_t {
    kNull = kTypedTagNull,
    kFalse = kTypedTagFalse,
    kTrue = kTypedTagTrue,
    kNumber = kTypedTagNumber,
    kString = kTypedTagString,
    kArray = kTypedTagArray,
    kObject = kTypedTagObject
  };

  class iterator;

  /// A null that belongs to no document (what a lookup of a missing member can stand for).
  TypedValue() = default;
  TypedValue(const TypedDocument* doc, std::uint32_t index) : doc_(doc), index_(index) {}

  Type type() const;
  bool is_null() const { return type() == Type::kNull; }
  bool is_boolean() const { return type() == Type::kFalse || type() == Type::kTrue; }
  bool is_number() const { return type() == Type::kNumber; }
  /// A number with no fraction (JavaScript has one number type: 3 and 3.0 are the same value).
  bool is_number_integer() const;
  bool is_number_unsigned() const { return is_number_integer() && number() >= 0; }
  bool is_string() const { return type() == Type::kString; }
  bool is_array() const { return type() == Type::kArray; }
  bool is_object() const { return type() == Type::kObject; }
  bool is_structured() const { return is_array() || is_object(); }

  /// Elements or members of a container, 0 for null, 1 for any other scalar (as nlohmann counts).
  std::size_t size() const;
  bool empty() const { return size() == 0; }
  /// The i-th element of an array (or member of an object, in key order); i < size().
  TypedValue operator[](std::size_t i) const;
  iterator begin() const;
  iterator end() const;
  /// The member with this key, or end(); end() for a value that is not an object.
  iterator find(std::string_view key) const;
  bool contains(std::string_view key) const;

  double number() const;
  bool boolean() const { return type() == Type::kTrue; }
  std::string_view string() const;
  /// nlohmann's get<T> for the types the readers ask for (double, float, bool, std::string, and
  /// the integer types from an integral number).
  template <typename T>
  T get() const;
  /// True for a string value equal to `text` (as nlohmann compares a value with a string).
  bool operator==(std::string_view text) const { return is_string() && string() == text; }
  bool operator!=(std::string_view text) const { return !(*this == text); }

 private:
  const TypedDocument* doc_ = nullptr;
  std::uint32_t index_ = 0;
};

/// Walks the children of a container (an object's in key order).
class TypedValue::iterator {
 public:
  iterator(const TypedDocument* doc, const std::uint32_t* slot) : doc_(doc), slot_(slot) {}
  const TypedValue& operator*() const { return current(); }
  const TypedValue* operator->() const { return &current(); }
  iterator& operator++() {
    ++slot_;
    return *this;
  }
  bool operator==(const iterator& other) const { return slot_ == other.slot_; }
  bool operator!=(const iterator& other) const { return slot_ != other.slot_; }
  /// The member's key (objects only).
  std::string key() const;

 private:
  const TypedValue& current() const {
    current_ = TypedValue(doc_, *slot_);
    return current_;
  }
  const TypedDocument* doc_;
  const std::uint32_t* slot_;
  mutable TypedValue current_;
};

template <>
double TypedValue::get<double>() const;
template <>
float TypedValue::get<float>() const;
template <>
bool TypedValue::get<bool>() const;
template <>
std::string TypedValue::get<std::string>() const;
template <>
std::int64_t TypedValue::get<std::int64_t>() const;
template <>
std::uint64_t TypedValue::get<std::uint64_t>() const;
template <>
int TypedValue::get<int>() const;

/// A decoded value: a flat table of values, children by index, so that nothing recurses (not the
/// decoder, not the destructor) however deeply the input nests.
class TypedDocument {
 public:
  /// Decodes `size` bytes at `data`, which must outlive the document (strings point into them).
  /// kInvalidArgument when the bytes are not exactly one value in the encoding; kLimitExceeded,
  /// with the JSON path of the value, past `max_bytes` or a bound above. Nothing is allocated for
  /// the table until the whole input has been checked, and then 16 bytes per value and 4 per child.
  Error decode(const std::uint8_t* data, std::size_t size, std::size_t max_bytes);
  TypedValue root() const { return TypedValue(this, 0); }

 private:
  friend class TypedValue;
  // 16 bytes: a number's bits and a key's length stay in data_, read when asked for.
  struct Node {
    TypedValue::Type type = TypedValue::Type::kNull;
    std::uint32_t count = 0;  ///< containers: children; strings: bytes
    std::uint32_t first = 0;  ///< containers: start in children_; strings, numbers: offset in data_
    std::uint32_t key = 0;    ///< object members: offset of the key's u32 length in data_
  };
  std::string_view keyOf(const Node& node) const;
  const std::uint8_t* data_ = nullptr;
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> children_;  ///< each container's children, contiguous, objects' by key
};

/// Writes the encoding of a value, for the producers on the C++ side (the readers, tests) and for
/// what the runtime hands the page (springbones/boundary.h, read by web/typed_output.js).
class TypedWriter {
 public:
  void null() { bytes_.push_back(kTypedTagNull); }
  void boolean(bool v) { bytes_.push_back(v ? kTypedTagTrue : kTypedTagFalse); }
  void number(double v);
  /// The tag float and the f32: a float of the runtime's output, which the page reads as the
  /// shortest decimal that gives the same float back. Typed input never holds it.
  void float32(float v);
  void string(std::string_view v);
  void array(std::uint32_t count);
  void object(std::uint32_t count);
  /// A member's key inside an object; its value follows.
  void key(std::string_view k) { sized(k); }
  std::vector<std::uint8_t>& bytes() { return bytes_; }

 private:
  void u32(std::uint32_t v);
  void sized(std::string_view v);
  std::vector<std::uint8_t> bytes_;
};

}  // namespace springbones
