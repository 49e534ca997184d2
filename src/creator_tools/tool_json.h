// The creator tools' JSON texts on nlohmann-json (springbones/creator_tools.h): reading an
// argument's text, and writing their results.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "creator_tools/builder_edits.h"
#include "creator_tools/validation.h"
#include "springbones/boundary.h"

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

/// Parses an argument's JSON text; a failure "<what>-bad-json" when it does not parse.
ApiFailure parseArgument(std::string_view text, const char* what, nlohmann::json& out);

/// JSON has no NaN or Infinity, but a JS object can hold them and the validator must reject them
/// as Ajv does ("must be number") rather than see the null JSON.stringify writes. The JS side
/// writes each non-finite number as the string marker + "NaN" (or "Infinity", "-Infinity"), with a
/// marker drawn at random per call so no real string can be taken for one; this puts the numbers
/// back. Iterative: the value may nest deeply. An empty marker changes nothing.
void restoreNonFinite(nlohmann::json& value, const std::string& marker);

/// [{path, message}].
std::string validationErrorsJson(const std::vector<ValidationError>& errors);

/// {contentHash, candidates: [{name, node, parent, hasEntry, isRoot, params, center?}], warnings}.
/// No center key: the runtime default; null: explicitly world space; else a node name.
std::string candidatesJson(const std::string& content_hash, const std::vector<SpringBoneCandidate>& candidates,
                           const std::vector<Warning>& warnings);

}  // namespace springbones
