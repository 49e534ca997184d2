// How deep a parsed JSON value nests. nlohmann's copy, dump and destructor recurse once per level,
// so a hostile document nested millions deep overflows the stack (the WebAssembly one first)
// unless it is measured first, without recursion, and refused or summarised.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace springbones {

/// True when `value` nests more than `max_depth` arrays/objects deep (a scalar has depth 0, an
/// object of scalars depth 1). Iterative.
inline bool nestsDeeperThan(const nlohmann::json& value, std::size_t max_depth) {
  std::vector<std::pair<const nlohmann::json*, std::size_t>> stack{{&value, 0}};
  while (!stack.empty()) {
    const auto [v, depth] = stack.back();
    stack.pop_back();
    if (!v->is_structured()) continue;
    if (depth >= max_depth) return true;
    for (const nlohmann::json& child : *v) stack.emplace_back(&child, depth + 1);
  }
  return false;
}

}  // namespace springbones
