// What the runtime's JavaScript API and the core exchange besides typed input (typed_input.h): the
// rig options, and the values it reads back (failures, the rig description, limits, stats) in the
// typed encoding (common/typed_value.h), which web/typed_output.js reads: no text is formatted for
// them, no number written in decimal (src/boundary/). The creator tools' texts are in
// creator_tools.h. The bindings (wasm/bindings.cpp) only pass these through.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "springbones/springbones.h"
#include "springbones/typed_input.h"
#include "springbones/vrm.h"

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
std::vector<std::uint8_t> describeFailure(const ApiFailure& failure);

/// The rig options loadRig's JS side writes, as typed input: {colliders?: [{node, shape?, offset?,
/// radius?, tail?, normal?, inside?}], preset?: "dcl-body", hitRadius?, limits?}; no bytes for none.
/// Checked by the rules web/rig_options.js checks the caller's options by (docs/semantics.md,
/// "Rig options"): a value it refuses is an "invalid-argument" failure whose path (a JSON pointer
/// into the options, "/colliders/0/radius") names what the JavaScript's error names.
ApiFailure readRigOptions(TypedBytes options, RigOptions& out);

/// Instance::setColliders' colliders as the JS side writes them (web/rig_options.js), as typed
/// input: {colliders?: [...as in the rig options], preset?: "dcl-body", avatarBones?, scale?,
/// omit?: [shape names]}, scale and omit only with the preset; no bytes: none. Refused values as
/// readRigOptions refuses them, the message starting "setColliders: ".
ApiFailure readColliderOptions(TypedBytes options, ColliderOptions& out);

/// What setColliders reports: {frames: [names, in frameMatrices' order], warnings: [...]}.
std::vector<std::uint8_t> describeColliderChange(const std::vector<std::string>& frames,
                                                 const std::vector<Warning>& warnings);

/// The rig: {contentHash, format, nodeCount, joints, chains, drivers, colliders, warnings}, with the
/// property names of web/springbones.d.ts. `content_hash` is the models key the rig was built
/// from, `format` where its springs came from (dcl, vrmc-springbone, vrm0, none). Members in key
/// order; floats as floats (the tag float), non-finite ones as null.
std::vector<std::uint8_t> describeRig(const Rig& rig, const std::string& content_hash, const std::string& format);

/// A built rig as bytes (src/boundary/rig_data.cpp has the layout), with the format its springs
/// were read from: how a rig the readers module builds (loadVrm) crosses into the runtime module,
/// so that the runtime carries no VRM reader. readRigData gives back the same rig, float for float;
/// bytes in another layout (or another build's) are a kInvalidArgument Error.
void writeRigData(const Rig& rig, VrmSpringFormat format, std::vector<std::uint8_t>& out);
Error readRigData(TypedBytes data, std::shared_ptr<const Rig>& out, VrmSpringFormat& format);

/// The limits and defaults the JS API checks its arguments against, as the core defines them:
/// {maxStepHz, maxSubsteps, maxXpbdIterations, maxMetadataBytes, integrators: {vrm: {stepHz,
/// maxSubsteps}, xpbd: {stepHz, maxSubsteps, xpbdIterations}}, bodyColliderShapes: the 'dcl-body' shape
/// names setColliders' omit takes (dclBodyShapeNames)}.
std::vector<std::uint8_t> describeLimits();

/// {rigs, instances, scenes, heapInUse}: the live handles and the bytes malloc has handed out.
std::vector<std::uint8_t> describeStats(std::size_t rigs, std::size_t instances, std::size_t scenes,
                                        std::size_t heap_in_use);

}  // namespace springbones
