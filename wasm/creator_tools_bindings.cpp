// embind bindings of the creator-tools module: deploy-time validation and the Builder edits
// (candidate detection, parameter writes), which a preview never runs. The same contract as the
// runtime module's wasm/bindings.cpp (binding_errors.h): strings and pointers only, 0 or "" with
// the error pending on failure, nothing thrown across the boundary. The caller is
// web/creator_tools.js. This module holds no handles: every call is a pure function of its
// arguments.
#include <cstdint>
#include <string>
#include <vector>

#include <emscripten/bind.h>

#include "binding_errors.h"
#include "heap_in_use.h"
#include "springbones/boundary.h"
#include "springbones/creator_tools.h"

namespace springbones::bindings {
namespace {

/// The catalyst's errors for the entity as JSON [{path, message}], or "" with the error pending.
std::string validateSpringBones(const std::string& entity_text, const std::string& marker) {
  std::string text;
  guarded([&] {
    if (ApiFailure f = springbones::validateSpringBones(entity_text, marker, text)) return fail(std::move(f));
    return 1;
  });
  return text;
}

/// The spring-bone candidates of a GLB with their prefill values, as JSON {contentHash,
/// candidates: [...], warnings: [...]}, or "" with the error pending. The same inputs as the
/// runtime's loadRig; the models key comes resolved (the runtime module reads the entity), or
/// empty for the GLB's own content hash.
std::string detectSpringBones(std::uintptr_t data, std::size_t size, const std::string& metadata,
                              const std::string& hash) {
  std::string text;
  guarded([&] {
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(data);
    if (ApiFailure f = springbones::detectSpringBones(bytes, size, metadata, hash, text)) return fail(std::move(f));
    return 1;
  });
  return text;
}

/// springBones with node_name's entry under the body shape's GLB hash set to params (JSON text;
/// "null" removes it), as JSON text, or "" with the error pending.
std::string setSpringBoneParams(const std::string& springbones_text, const std::string& entity_text,
                                const std::string& body_shape, const std::string& node_name,
                                const std::string& params_text) {
  std::string text;
  guarded([&] {
    if (ApiFailure f =
            springbones::setSpringBoneParams(springbones_text, entity_text, body_shape, node_name, params_text, text)) {
      return fail(std::move(f));
    }
    return 1;
  });
  return text;
}

/// Diagnostics for leak tests: the bytes requested from malloc and not freed (this module holds no
/// handles), as the typed result.
int stats() {
  // The previous typed result freed first, so that the bytes in use do not count it.
  g_result = std::vector<std::uint8_t>();
  return result(describeStats(0, 0, 0, heapInUse()));
}

}  // namespace
}  // namespace springbones::bindings

EMSCRIPTEN_BINDINGS(springbones_creator_tools) {
  using namespace springbones::bindings;
  emscripten::function("takeError", &takeError);
  emscripten::function("validateSpringBones", &validateSpringBones);
  emscripten::function("detectSpringBones", &detectSpringBones);
  emscripten::function("setSpringBoneParams", &setSpringBoneParams);
  emscripten::function("stats", &stats);
  emscripten::function("typedResult", &typedResult);
}
