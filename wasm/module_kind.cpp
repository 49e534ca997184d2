// Which of the two builds of the runtime this is (wasm/CMakeLists.txt): the crowd module (the
// per-frame path at -O3 with SIMD) or the runtime a preview downloads. Compiled for each with its
// SPRINGBONES_CROWD_MODULE; the JS API reads it as sb.crowd (web/runtime_calls.js).
#include <emscripten/emscripten.h>

#ifndef SPRINGBONES_CROWD_MODULE
#error "wasm/CMakeLists.txt defines SPRINGBONES_CROWD_MODULE (0 or 1) for each runtime module"
#endif

extern "C" EMSCRIPTEN_KEEPALIVE int sb_isCrowdModule() { return SPRINGBONES_CROWD_MODULE != 0 ? 1 : 0; }
