#include "common/typed_value.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "common/shown_name.h"

namespace springbones {
namespace {

Error malformed(const std::string& why) {
  return Error{ErrorCode::kInvalidArgument, "typed input is malformed: " + why, ""};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Decoding, in two passes with explicit stacks (no recursion at any depth). The first checks the
// bytes and every bound and counts the values, allocating nothing but its stack, so a refused
// input leaves the table unallocated; the second fills a table sized exactly. A container's
// children get contiguous slots in children_ when it opens; an object's are sorted by key when it
// closes.

namespace {

std::uint32_t readU32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) | (std::uint32_t(p[3]) << 24);
}

Error tooLarge(const std::string& what, std::size_t limit, const std::string& path) {
  return Error{ErrorCode::kLimitExceeded, "typed input: " + what + ", more than the limit of " + std::to_string(limit),
               path};
}

// One open container of the first pass: where the path to the value being read goes through it.
struct Open {
  std::uint32_t count;
  std::uint32_t remaining;
  std::uint32_t key;  ///< objects: offset of the current member's key length; arrays: UINT32_MAX
};

std::string pathOf(const std::vector<Open>& open, const std::uint8_t* data) {
  std::string path;
  for (const Open& o : open) {
    if (o.key == std::numeric_limits<std::uint32_t>::max()) {
      path += "/" + std::to_string(o.count - o.remaining - 1);
    } else {
      const std::uint32_t size = readU32(data + o.key);
      // A path quotes at most a bounded prefix of a key, as a message quotes a name.
      path += "/" + shownName(std::string_view(reinterpret_cast<const char*>(data + o.key + 4), size));
    }
  }
  return path;
}

}  // namespace

Error TypedDocument::decode(const std::uint8_t* data, std::size_t size, std::size_t max_bytes) {
  data_ = data;
  nodes_.clear();
  children_.clear();
  if (data == nullptr && size != 0) return malformed("no bytes");
  if (size > max_bytes || size > std::numeric_limits<std::uint32_t>::max()) {
    return tooLarge(std::to_string(size) + " bytes", std::min<std::size_t>(max_bytes, 0xFFFFFFFFu), "");
  }
  // Pass 1: structure and bounds.
  std::vector<Open> open;
  std::size_t at = 0;
  std::size_t values = 0;
  const auto sized = [&](std::uint32_t& length) {
    if (size - at < 4) return false;
    length = readU32(data + at);
    at += 4;
    if (size - at < length) return false;
    at += length;
    return true;
  };
  do {
    std::uint32_t length = 0;
    if (!open.empty() && open.back().key != std::numeric_limits<std::uint32_t>::max()) {
      open.back().key = static_cast<std::uint32_t>(at);
      if (!sized(length)) return malformed("an object member's key runs past the end");
      if (length > kTypedMaxStringBytes) {
        return tooLarge("a key of " + std::to_string(length) + " bytes", kTypedMaxStringBytes, pathOf(open, data));
      }
    }
    if (at >= size) return malformed("a value is missing at byte " + std::to_string(at));
    // Counted as read before it is checked, so every open container's path names its open child.
    if (!open.empty()) --open.back().remaining;
    if (++values > kTypedMaxValues) return tooLarge("more values", kTypedMaxValues, pathOf(open, data));
    const std::uint8_t tag = data[at++];
    const auto type = static_cast<TypedValue::Type>(tag);
    if (tag > kTypedTagObject)
      return malformed("unknown tag " + std::to_string(tag) + " at byte " + std::to_string(at - 1));
    if (type == TypedValue::Type::kNumber) {
      if (size - at < 8) return malformed("a number runs past the end");
      at += 8;
    } else if (type == TypedValue::Type::kString) {
      if (!sized(length)) return malformed("a string runs past the end");
      if (length > kTypedMaxStringBytes) {
        return tooLarge("a string of " + std::to_string(length) + " bytes", kTypedMaxStringBytes, pathOf(open, data));
      }
    }
    if (type == TypedValue::Type::kArray || type == TypedValue::Type::kObject) {
      if (size - at < 4) return malformed("a container's count runs past the end");
      const std::uint32_t count = readU32(data + at);
      at += 4;
      if (count > kTypedMaxContainerSize) {
        const std::string path = pathOf(open, data);
        return tooLarge(std::string(type == TypedValue::Type::kArray ? "an array of " : "an object of ") +
                            std::to_string(count) + (type == TypedValue::Type::kArray ? " elements" : " members"),
                        kTypedMaxContainerSize, path);
      }
      // Every element takes at least one byte (a member five): a count beyond that is a lie.
      if (count > size - at) return malformed("a container's count runs past the end");
      open.push_back(
          Open{count, count, type == TypedValue::Type::kObject ? 0u : std::numeric_limits<std::uint32_t>::max()});
    }
    while (!open.empty() && open.back().remaining == 0) open.pop_back();
  } while (!open.empty());
  if (at != size) return malformed(std::to_string(size - at) + " bytes after the value");
  open.clear();
  open.shrink_to_fit();

  // Pass 2: the table. The bytes are known to be well formed and within bounds.
  nodes_.resize(values);
  children_.resize(values - 1);
  struct Fill {
    std::uint32_t node;
    std::uint32_t next;  ///< the next free child slot of this container
  };
  std::vector<Fill> stack;
  std::uint32_t free_slot = 0;
  at = 0;
  for (std::uint32_t index = 0; index < values; ++index) {
    Node& node = nodes_[index];
    if (!stack.empty()) {
      if (nodes_[stack.back().node].type == TypedValue::Type::kObject) {
        node.key = static_cast<std::uint32_t>(at);
        at += 4 + readU32(data + at);
      }
      children_[stack.back().next++] = index;
    }
    node.type = static_cast<TypedValue::Type>(data[at++]);
    if (node.type == TypedValue::Type::kNumber) {
      node.first = static_cast<std::uint32_t>(at);
      at += 8;
    } else if (node.type == TypedValue::Type::kString) {
      node.count = readU32(data + at);
      node.first = static_cast<std::uint32_t>(at + 4);
      at += 4 + node.count;
    } else if (node.type == TypedValue::Type::kArray || node.type == TypedValue::Type::kObject) {
      node.count = readU32(data + at);
      at += 4;
      node.first = free_slot;
      free_slot += node.count;
      stack.push_back(Fill{index, node.first});
    }
    while (!stack.empty() && stack.back().next == nodes_[stack.back().node].first + nodes_[stack.back().node].count) {
      const Node& container = nodes_[stack.back().node];
      if (container.type == TypedValue::Type::kObject) {
        std::sort(children_.begin() + container.first, children_.begin() + container.first + container.count,
                  [&](std::uint32_t a, std::uint32_t b) { return keyOf(nodes_[a]) < keyOf(nodes_[b]); });
      }
      stack.pop_back();
    }
  }
  return {};
}

std::string_view TypedDocument::keyOf(const Node& node) const {
  return std::string_view(reinterpret_cast<const char*>(data_ + node.key + 4), readU32(data_ + node.key));
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
  const std::uint32_t* it = std::lower_bound(
      first, last, key, [&](std::uint32_t child, std::string_view k) { return doc_->keyOf(doc_->nodes_[child]) < k; });
  if (it != last) {
    if (doc_->keyOf(doc_->nodes_[*it]) == key) { return iterator(doc_, it); }
  }
  return end();
}

bool TypedValue::contains(std::string_view key) const { return find(key) != end(); }

double TypedValue::number() const {
  if (!is_number()) return 0.0;
  const std::uint8_t* p = doc_->data_ + doc_->nodes_[index_].first;
  std::uint64_t bits = 0;
  for (int i = 7; i >= 0; --i) bits = (bits << 8) | p[i];
  double v = 0;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

std::string_view TypedValue::string() const {
  if (!is_string()) return {};
  const auto& n = doc_->nodes_[index_];
  return std::string_view(reinterpret_cast<const char*>(doc_->data_ + n.first), n.count);
}

std::string TypedValue::iterator::key() const { return std::string(doc_->keyOf(doc_->nodes_[*slot_])); }

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
  bytes_.push_back(kTypedTagNumber);
  std::uint64_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
}

void TypedWriter::float32(float v) {
  bytes_.push_back(kTypedTagFloat);
  std::uint32_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  u32(bits);
}

void TypedWriter::string(std::string_view v) {
  bytes_.push_back(kTypedTagString);
  sized(v);
}

void TypedWriter::array(std::uint32_t count) {
  bytes_.push_back(kTypedTagArray);
  u32(count);
}

void TypedWriter::object(std::uint32_t count) {
  bytes_.push_back(kTypedTagObject);
  u32(count);
}

}  // namespace springbones
