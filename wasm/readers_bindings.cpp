// embind bindings of the readers module: GLB / glTF bytes into typed input for the runtime
// (springbones/readers.h), and a VRM document's typed input into the rig the runtime runs
// (springbones/boundary.h, rig data). Contract with web/readers.js (the only caller): readGltf
// and readVrm return the length of what they wrote, or -1 with the error pending (takeError, as in
// the runtime); typedResult() is where those bytes are, until the next call (binding_errors.h).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <emscripten/bind.h>

#include "binding_errors.h"
#include "springbones/boundary.h"
#include "springbones/readers.h"
#include "springbones/typed_input.h"

namespace springbones::bindings {
namespace {

void clearResult() {
  g_result.clear();
  g_result.shrink_to_fit();
}

int readGltf(std::uintptr_t data, std::size_t size, bool with_extensions) {
  clearResult();
  const int ok = guarded([&] {
    const GltfPart part = with_extensions ? GltfPart::kNodesAndExtensions : GltfPart::kNodes;
    if (Error e = springbones::readGltf(reinterpret_cast<const std::uint8_t*>(data), size, part, g_result)) {
      return fail(e);
    }
    return 1;
  });
  return ok ? static_cast<int>(g_result.size()) : -1;
}

/// The VRM rules (springbones/vrm.h) on a document's typed {asset, nodes, extensions}: the rig as
/// rig data, its errors those of loadVrm.
int readVrm(std::uintptr_t typed, std::size_t size) {
  clearResult();
  const int ok = guarded([&] {
    std::shared_ptr<const Rig> rig;
    VrmSpringFormat format = VrmSpringFormat::kNone;
    const TypedBytes gltf{reinterpret_cast<const std::uint8_t*>(typed), size};
    if (Error e = springbones::loadVrm(gltf, rig, &format)) return fail(e);
    writeRigData(*rig, format, g_result);
    return 1;
  });
  return ok ? static_cast<int>(g_result.size()) : -1;
}

}  // namespace
}  // namespace springbones::bindings

EMSCRIPTEN_BINDINGS(springbones_readers) {
  using namespace springbones::bindings;
  emscripten::function("takeError", &takeError);
  emscripten::function("readGltf", &readGltf);
  emscripten::function("readVrm", &readVrm);
  emscripten::function("typedResult", &typedResult);
}
