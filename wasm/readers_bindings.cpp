// embind bindings of the readers module: GLB / glTF bytes into typed input for the runtime
// (springbones/readers.h). Contract with web/readers.js (the only caller): readGltf returns the
// length of the typed input it wrote, or -1 with the error pending (takeError, as in the runtime);
// typedResult() is where those bytes are, until the next readGltf.
#include <cstdint>
#include <string>
#include <vector>

#include <emscripten/bind.h>

#include "binding_errors.h"
#include "springbones/readers.h"

namespace springbones::bindings {
namespace {

std::vector<std::uint8_t> g_result;

int readGltf(std::uintptr_t data, std::size_t size, bool with_extensions) {
  g_result.clear();
  g_result.shrink_to_fit();
  const int ok = guarded([&] {
    const GltfPart part = with_extensions ? GltfPart::kNodesAndExtensions : GltfPart::kNodes;
    if (Error e = springbones::readGltf(reinterpret_cast<const std::uint8_t*>(data), size, part, g_result)) {
      return fail(e);
    }
    return 1;
  });
  return ok ? static_cast<int>(g_result.size()) : -1;
}

std::uintptr_t typedResult() { return reinterpret_cast<std::uintptr_t>(g_result.data()); }

}  // namespace
}  // namespace springbones::bindings

EMSCRIPTEN_BINDINGS(springbones_readers) {
  using namespace springbones::bindings;
  emscripten::function("takeError", &takeError);
  emscripten::function("readGltf", &readGltf);
  emscripten::function("typedResult", &typedResult);
}
