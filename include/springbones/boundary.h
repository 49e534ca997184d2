// The JSON texts the JavaScript API and the core exchange (the creator tools' are in
// creator_tools.h): the arguments web/springbones.js hands over as text and the results it reads
// back. The bindings (wasm/bindings.cpp) only pass these strings through; the JSON reading and
// writing stays inside the core (src/boundary/).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

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

/// The rig options loadRig's JS side writes after checking every field: {"colliders": [{"node",
/// "offset": [x,y,z], "radius"?, "tail"?: [x,y,z], "normal"?: [x,y,z], "inside"?: bool}],
/// "preset"?: "dcl-body", "hitRadius"} (a collider with a normal is a plane, else one with a tail
/// a capsule, else a sphere); empty text for none. An "invalid-argument" failure for any other
/// shape.
ApiFailure readRigOptions(std::string_view text, RigOptions& out);

/// The GLB hash of the representation `body_shape` wears in the entity or Builder item given as
/// JSON text: an "entity-bad-json" failure when the text does not parse, else mainFileHashFor's
/// errors (an unknown body shape, a main file missing from the content list).
ApiFailure mainFileHashFor(std::string_view entity_text, const std::string& body_shape, std::string& hash);

/// The rig as JSON text: {contentHash, format, nodeCount, joints, chains, drivers, colliders,
/// warnings}, with the property names of web/springbones.d.ts. `content_hash` is the models key
/// the rig was built from, `format` where its springs came from (dcl, vrmc-springbone, vrm0, none).
/// Non-finite floats are written as null; strings that are not UTF-8 with U+FFFD in their place.
std::string describeRig(const Rig& rig, const std::string& content_hash, const std::string& format);

/// The limits and defaults the JS API checks its arguments against, as the core defines them:
/// {maxStepHz, maxSubsteps, maxXpbdIterations, maxMetadataBytes, integrators: {vrm: {stepHz,
/// maxSubsteps}, xpbd: {stepHz, maxSubsteps, xpbdIterations}}}.
std::string limitsJson();

/// {rigs, instances, scenes, heapInUse}: the live handles and the bytes malloc has handed out.
std::string statsJson(std::size_t rigs, std::size_t instances, std::size_t scenes, std::size_t heap_in_use);

}  // namespace springbones
