// The JSON texts web/springbones.js and the core exchange, other than the rig description
// (rig_description.h): the arguments it hands over as text and the results it reads back. The
// bindings (wasm/bindings.cpp) only pass these strings through.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "creator_tools/builder_edits.h"
#include "creator_tools/validation.h"
#include "springbones/springbones.h"

namespace springbones {

/// A failure as the JS API reports it (SpringBonesError): a core Error's code name, or a code that
/// only exists at the boundary ("entity-bad-json", "out-of-memory", "bad-handle"...).
struct ApiFailure {
  std::string code;  ///< empty: no failure
  std::string message;
  std::string path;
  explicit operator bool() const { return !code.empty(); }
};

ApiFailure toFailure(const Error& error);
/// {code, message, path}.
std::string failureJson(const ApiFailure& failure);

/// Parses an argument's JSON text; a failure "<what>-bad-json" when it does not parse.
ApiFailure parseArgument(std::string_view text, const char* what, nlohmann::json& out);

/// The rig options loadRig's JS side writes after checking every field: {"colliders": [{"node",
/// "offset": [x,y,z], "radius", "tail"?: [x,y,z]}], "hitRadius"} (a collider with a tail is a
/// capsule); empty text for none. An "invalid-argument" failure for any other shape.
ApiFailure readRigOptions(std::string_view text, RigOptions& out);

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

/// The limits and defaults the JS API checks its arguments against, as the core defines them:
/// {maxStepHz, maxSubsteps, maxXpbdIterations, maxMetadataBytes, integrators: {vrm: {stepHz,
/// maxSubsteps}, xpbd: {stepHz, maxSubsteps, xpbdIterations}}}.
std::string limitsJson();

/// {rigs, instances, scenes, heapInUse}: the live handles and the bytes malloc has handed out.
std::string statsJson(std::size_t rigs, std::size_t instances, std::size_t scenes, std::size_t heap_in_use);

}  // namespace springbones
