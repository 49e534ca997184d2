// The JSON values the boundary writes (describeRig, springbones/boundary.h, and the other results):
// floats as the shortest text that reads back as the same float, untrusted strings made UTF-8.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace springbones {

/// A JSON value whose numbers with a fraction are floats: the values the simulation uses, dumped
/// as the shortest text that reads back as the same float (0.4f as 0.4, not 0.4000000059604645).
using FloatJson = nlohmann::basic_json<std::map, std::vector, std::string, bool, std::int64_t, std::uint64_t, float>;

/// dump() of a value holding strings from untrusted input: bytes that are not UTF-8 become U+FFFD
/// instead of an exception.
template <typename Json>
std::string dumpReplacingInvalidUtf8(const Json& value) {
  return value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace springbones
