// Name -> first value with that name, over views of strings that outlive the index: the core's one
// map keyed by name (nodes, metadata entries, collider nodes, content files).
#pragma once

#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

namespace springbones {

// Open addressing in one flat array: std::unordered_map allocated a node per name (7,000 for a
// large wearable) and was a third of the build, and its template code is bytes in every module.
// reserve(count) comes first, with at least as many names as will be inserted; values are >= 0.
class NameIndex {
 public:
  void reserve(std::size_t count) {
    std::size_t size = 16;
    while (size < 2 * count) size *= 2;
    slots_.assign(size, Slot{});
    mask_ = size - 1;
  }

  /// Adds name -> value unless the name is there already (the first one is kept).
  void insertFirst(std::string_view name, int value) {
    const std::uint32_t h = hash(name);
    for (std::size_t i = h & mask_;; i = (i + 1) & mask_) {
      Slot& s = slots_[i];
      if (s.value < 0) {
        s = Slot{name.data(), static_cast<std::uint32_t>(name.size()), h, value};
        return;
      }
      if (s.hash == h && equal(s, name)) return;
    }
  }

  /// The value of `name`, or -1.
  int find(std::string_view name) const {
    if (slots_.empty()) return -1;
    const std::uint32_t h = hash(name);
    for (std::size_t i = h & mask_;; i = (i + 1) & mask_) {
      const Slot& s = slots_[i];
      if (s.value < 0) return -1;
      if (s.hash == h && equal(s, name)) return s.value;
    }
  }

 private:
  struct Slot {
    const char* data = nullptr;
    std::uint32_t size = 0;
    std::uint32_t hash = 0;
    int value = -1;  ///< -1: empty
  };

  static bool equal(const Slot& s, std::string_view name) {
    return s.size == name.size() && std::memcmp(s.data, name.data(), name.size()) == 0;
  }

  // FNV-1a, then a final mix so that names differing only in their last bytes spread out.
  static std::uint32_t hash(std::string_view name) {
    std::uint32_t h = 2166136261u;
    for (char c : name) h = (h ^ static_cast<unsigned char>(c)) * 16777619u;
    h ^= h >> 15;
    h *= 0x2c1b3c6du;
    h ^= h >> 12;
    return h;
  }

  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
};

}  // namespace springbones
