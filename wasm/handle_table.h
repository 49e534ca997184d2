// The runtime's live rigs, instances and scenes by handle. Handles only grow (bindings.cpp never
// reuses one), so appending keeps the table sorted and a lookup is a binary search: one vector per
// table instead of std::unordered_map, whose hashing and rehashing were code in every preview's
// download (docs/performance.md, "Every byte"). Lookups are a few per call, over the tens of
// objects a page holds.
#pragma once

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace springbones::bindings {

template <typename T>
class HandleTable {
 public:
  using Entry = std::pair<int, T>;
  using iterator = typename std::vector<Entry>::iterator;

  iterator begin() { return entries_.begin(); }
  iterator end() { return entries_.end(); }
  std::size_t size() const { return entries_.size(); }

  iterator find(int handle) {
    auto it = std::lower_bound(entries_.begin(), entries_.end(), handle,
                               [](const Entry& entry, int h) { return entry.first < h; });
    return it != entries_.end() && it->first == handle ? it : entries_.end();
  }

  /// Adds a handle newer than every handle in the table.
  void emplace(int handle, T value) { entries_.emplace_back(handle, std::move(value)); }

  void erase(iterator it) { entries_.erase(it); }
  /// Removes the handle; the number removed (0 or 1).
  std::size_t erase(int handle) {
    auto it = find(handle);
    if (it == entries_.end()) return 0;
    entries_.erase(it);
    return 1;
  }

 private:
  std::vector<Entry> entries_;
};

}  // namespace springbones::bindings
