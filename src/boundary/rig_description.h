// The rig description the JS API shows as rig.joints, rig.chains, rig.drivers, rig.colliders and
// rig.warnings: one JSON text, written here and parsed once on the JS side.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "springbones/springbones.h"

namespace springbones {

/// A JSON value whose numbers with a fraction are floats: the values the simulation uses, dumped
/// as the shortest text that reads back as the same float (0.4f as 0.4, not 0.4000000059604645).
using FloatJson = nlohmann::basic_json<std::map, std::vector, std::string, bool, std::int64_t, std::uint64_t, float>;

/// The rig as JSON text: {contentHash, format, nodeCount, joints, chains, drivers, colliders,
/// warnings}, with the property names of web/springbones.d.ts. `content_hash` is the models key
/// the rig was built from, `format` where its springs came from (dcl, vrmc-springbone, vrm0, none).
/// Non-finite floats are written as null; strings that are not UTF-8 with U+FFFD in their place.
std::string describeRig(const Rig& rig, const std::string& content_hash, const std::string& format);

/// dump() of a value holding strings from untrusted input: bytes that are not UTF-8 become U+FFFD
/// instead of an exception.
template <typename Json>
std::string dumpReplacingInvalidUtf8(const Json& value) {
  return value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace springbones
