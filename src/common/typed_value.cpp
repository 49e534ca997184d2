#include "common/typed_value.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

namespace springbones {
namespace {

Error malformed(const std::string& why) {
  return Error{ErrorCode::kInvalidArgument, "typed input is malformed: " + why, ""};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Decoding: one pass over the bytes with an explicit stack of open containers. A container's
// children are collected on its frame and appended to children_ when it closes, so each one's are
// contiguous; an object's are sorted by key first.

Error TypedDocument::decode(const std::uint8_t* data, std::size_t size) {
  data_ = data;
  nodes_.clear();
  children_.clear();
  if (data == nullptr && size != 0) return malformed("no bytes");
  if (size > std::numeric_limits<std::uint32_t>::max()) return malformed("more than 4 GiB");
  struct Frame {
    std::uint32_t node;
    std::uint32_t remaining;
    std::vector<std::uint32_t> children;
  };
  std::vector<Frame> open;
  std::size_t at = 0;
  const auto u32 = [&](std::uint32_t& out) {
    if (size - at < 4) return false;
    out = std::uint32_t(data[at]) | (std::uint32_t(data[at + 1]) << 8) | (std::uint32_t(data[at + 2]) << 16) |
          (std::uint32_t(data[at + 3]) << 24);
    at += 4;
    return true;
  };
  const auto sized = [&](std::uint32_t& offset, std::uint32_t& length) {
    if (!u32(length) || size - at < length) return false;
    offset = static_cast<std::uint32_t>(at);
    at += length;
    return true;
  };
  do {
    Node node;
    if (!open.empty() && nodes_[open.back().node].type == TypedValue::Type::kObject) {
      if (!sized(node.key, node.key_size)) return malformed("an object member's key runs past the end");
    }
    if (at >= size) return malformed("a value is missing at byte " + std::to_string(at));
    const std::uint8_t tag = data[at++];
    if (tag > 6) return malformed("unknown tag " + std::to_string(tag) + " at byte " + std::to_string(at - 1));
    node.type = static_cast<TypedValue::Type>(tag);
    if (node.type == TypedValue::Type::kNumber) {
      if (size - at < 8) return malformed("a number runs past the end");
      std::uint64_t bits = 0;
      for (int i = 7; i >= 0; --i) bits = (bits << 8) | data[at + i];
      std::memcpy(&node.number, &bits, sizeof node.number);
      at += 8;
    } else if (node.type == TypedValue::Type::kString) {
      if (!sized(node.first, node.count)) return malformed("a string runs past the end");
    } else if (node.type == TypedValue::Type::kArray || node.type == TypedValue::Type::kObject) {
      // Every element takes at least one byte (a member five): a count beyond that is a lie, and
      // must not size an allocation.
      if (!u32(node.count) || node.count > size - at) return malformed("a container's count runs past the end");
    }
    const auto index = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back(node);
    if (!open.empty()) {
      open.back().children.push_back(index);
      --open.back().remaining;
    }
    if ((node.type == TypedValue::Type::kArray || node.type == TypedValue::Type::kObject)) {
      open.push_back(Frame{index, node.count, {}});
    }
    while (!open.empty() && open.back().remaining == 0) {
      Frame& frame = open.back();
      Node& container = nodes_[frame.node];
      if (container.type == TypedValue::Type::kObject) {
        std::sort(frame.children.begin(), frame.children.end(), [&](std::uint32_t a, std::uint32_t b) {
          const Node& x = nodes_[a];
          const Node& y = nodes_[b];
          return std::string_view(reinterpret_cast<const char*>(data_ + x.key), x.key_size) <
                 std::string_view(reinterpret_cast<const char*>(data_ + y.key), y.key_size);
        });
      }
      container.first = static_cast<std::uint32_t>(children_.size());
      children_.insert(children_.end(), frame.children.begin(), frame.children.end());
      open.pop_back();
    }
  } while (!open.empty());
  if (at != size) return malformed(std::to_string(size - at) + " bytes after the value");
  return {};
}

// ---------------------------------------------------------------------------------------------
// The view

TypedValue::Type TypedValue::type() const { return doc_ == nullptr ? Type::kNull : doc_->nodes_[index_].type; }

bool TypedValue::is_number_integer() const {
  if (!is_number()) return false;
  const double v = number();
  return std::isfinite(v) && std::trunc(v) == v;
}

std::size_t TypedValue::size() const {
  switch (type()) {
    case Type::kNull: return 0;
    case Type::kArray:
    case Type::kObject: return doc_->nodes_[index_].count;
    default: return 1;
  }
}

TypedValue TypedValue::operator[](std::size_t i) const {
  return TypedValue(doc_, doc_->children_[doc_->nodes_[index_].first + i]);
}

TypedValue::iterator TypedValue::begin() const {
  if (!is_structured()) return end();
  return iterator(doc_, doc_->children_.data() + doc_->nodes_[index_].first);
}

TypedValue::iterator TypedValue::end() const {
  if (!is_structured()) return iterator(doc_, nullptr);
  const auto& node = doc_->nodes_[index_];
  return iterator(doc_, doc_->children_.data() + node.first + node.count);
}

TypedValue::iterator TypedValue::find(std::string_view key) const {
  if (!is_object()) return end();
  const auto& node = doc_->nodes_[index_];
  const std::uint32_t* first = doc_->children_.data() + node.first;
  const std::uint32_t* last = first + node.count;
  const std::uint32_t* it = std::lower_bound(first, last, key, [&](std::uint32_t child, std::string_view k) {
    const auto& n = doc_->nodes_[child];
    return std::string_view(reinterpret_cast<const char*>(doc_->data_ + n.key), n.key_size) < k;
  });
  if (it != last) {
    const auto& n = doc_->nodes_[*it];
    if (std::string_view(reinterpret_cast<const char*>(doc_->data_ + n.key), n.key_size) == key) {
      return iterator(doc_, it);
    }
  }
  return end();
}

bool TypedValue::contains(std::string_view key) const { return find(key) != end(); }

double TypedValue::number() const { return is_number() ? doc_->nodes_[index_].number : 0.0; }

std::string_view TypedValue::string() const {
  if (!is_string()) return {};
  const auto& n = doc_->nodes_[index_];
  return std::string_view(reinterpret_cast<const char*>(doc_->data_ + n.first), n.count);
}

std::string TypedValue::iterator::key() const {
  const auto& n = doc_->nodes_[*slot_];
  return std::string(reinterpret_cast<const char*>(doc_->data_ + n.key), n.key_size);
}

template <>
double TypedValue::get<double>() const {
  return number();
}
template <>
float TypedValue::get<float>() const {
  return static_cast<float>(number());
}
template <>
bool TypedValue::get<bool>() const {
  return boolean();
}
template <>
std::string TypedValue::get<std::string>() const {
  return std::string(string());
}
template <>
std::int64_t TypedValue::get<std::int64_t>() const {
  const double v = number();
  // Saturated: callers compare against their own bounds, and a cast of an out-of-range double is
  // undefined behaviour.
  if (!(v > -9.2e18)) return std::numeric_limits<std::int64_t>::min();
  if (!(v < 9.2e18)) return std::numeric_limits<std::int64_t>::max();
  return static_cast<std::int64_t>(v);
}
template <>
std::uint64_t TypedValue::get<std::uint64_t>() const {
  const double v = number();
  if (!(v > 0)) return 0;
  if (!(v < 1.8e19)) return std::numeric_limits<std::uint64_t>::max();
  return static_cast<std::uint64_t>(v);
}
template <>
int TypedValue::get<int>() const {
  const std::int64_t v = get<std::int64_t>();
  return static_cast<int>(
      std::clamp<std::int64_t>(v, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
}

// ---------------------------------------------------------------------------------------------
// Writing

void TypedWriter::u32(std::uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

void TypedWriter::sized(std::string_view v) {
  u32(static_cast<std::uint32_t>(v.size()));
  bytes_.insert(bytes_.end(), v.begin(), v.end());
}

void TypedWriter::number(double v) {
  bytes_.push_back(3);
  std::uint64_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
}

void TypedWriter::string(std::string_view v) {
  bytes_.push_back(4);
  sized(v);
}

void TypedWriter::array(std::uint32_t count) {
  bytes_.push_back(5);
  u32(count);
}

void TypedWriter::object(std::uint32_t count) {
  bytes_.push_back(6);
  u32(count);
}

}  // namespace springbones
