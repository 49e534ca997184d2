// embind bindings of the creator-tools module: deploy-time validation and the Builder edits
// (candidate detection, parameter writes), which a preview never runs. The same contract as the
// runtime module's wasm/bindings.cpp (binding_errors.h): strings and pointers only, 0 or "" with
// the error pending on failure, nothing thrown across the boundary. The caller is
// web/creator_tools.js. This module holds no handles: every call is a pure function of its
// arguments.
#include <malloc.h>

#include <cstdint>
#include <string>
#include <vector>

#include <emscripten/bind.h>
#include <nlohmann/json.hpp>

#include "binding_errors.h"
#include "boundary/api_json.h"
#include "boundary/rig_description.h"
#include "content_hash/content_hash.h"
#include "creator_tools/builder_edits.h"
#include "creator_tools/validation.h"
#include "springbones/springbones.h"

namespace springbones {
namespace {

using bindings::fail;
using bindings::guarded;
using nlohmann::json;

/// The catalyst's errors for the entity as JSON [{path, message}], or "" with the error pending.
std::string validateEntity(const std::string& entity_text, const std::string& marker) {
  std::string text;
  guarded([&] {
    json entity;
    if (ApiFailure f = parseArgument(entity_text, "entity", entity)) return fail(std::move(f));
    restoreNonFinite(entity, marker);
    std::vector<ValidationError> errors;
    if (Error e = validateSpringBones(entity, errors)) return fail(e);
    text = validationErrorsJson(errors);
    return 1;
  });
  return text;
}

/// The spring-bone candidates of a GLB with their prefill values, as JSON {contentHash,
/// candidates: [...], warnings: [...]}, or "" with the error pending. The same inputs as the
/// runtime's loadRig; the models key comes resolved (the runtime module reads the entity), or
/// empty for the GLB's own content hash.
std::string detectCandidates(std::uintptr_t data, std::size_t size, const std::string& metadata,
                             const std::string& hash) {
  std::string text;
  guarded([&] {
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(data);
    Skeleton skeleton;
    if (Error e = loadSkeleton(bytes, size, skeleton)) return fail(e);
    const std::string key = hash.empty() ? contentHash(bytes, size) : hash;
    ModelEntry model;
    std::vector<Warning> warnings;
    if (Error e = parseSpringBonesText(metadata, key, model, warnings)) return fail(e);
    text = candidatesJson(key, detectSpringBones(skeleton, model), warnings);
    return 1;
  });
  return text;
}

/// springBones with node_name's entry under the body shape's GLB hash set to params (JSON text;
/// "null" removes it), as JSON text, or "" with the error pending.
std::string setParams(const std::string& springbones_text, const std::string& entity_text,
                      const std::string& body_shape, const std::string& node_name,
                      const std::string& params_text) {
  std::string text;
  guarded([&] {
    json springBones, entity, params, out;
    if (ApiFailure f = parseArgument(springbones_text, "metadata", springBones)) return fail(std::move(f));
    if (ApiFailure f = parseArgument(entity_text, "entity", entity)) return fail(std::move(f));
    if (ApiFailure f = parseArgument(params_text, "params", params)) return fail(std::move(f));
    if (Error e = setSpringBoneParams(springBones, entity, body_shape, node_name, params, out)) return fail(e);
    text = dumpReplacingInvalidUtf8(out);  // at most 64 levels deep
    return 1;
  });
  return text;
}

/// Diagnostics for leak tests: the bytes malloc has handed out (this module holds no handles).
std::string stats() {
  const struct mallinfo info = mallinfo();
  return statsJson(0, 0, 0, static_cast<std::size_t>(info.uordblks));
}

}  // namespace
}  // namespace springbones

EMSCRIPTEN_BINDINGS(springbones_creator_tools) {
  using namespace springbones;
  emscripten::function("takeError", &bindings::takeError);
  emscripten::function("validateEntity", &validateEntity);
  emscripten::function("detectCandidates", &detectCandidates);
  emscripten::function("setParams", &setParams);
  emscripten::function("stats", &stats);
}
