// What every bindings file of a module shares (wasm/bindings.cpp for the runtime module,
// wasm/readers_bindings.cpp, wasm/creator_tools_bindings.cpp): the pending error, the guard that
// turns any C++ exception into one, and the typed result, where an entry point leaves bytes for
// the JavaScript to copy out. Each module is its own WebAssembly instance with its own
// memory, so each has its own pending error; `inline` keeps one per module however many files
// include this.
//
// Contract with the JavaScript side: an entry point that fails returns 0 (or "") and leaves the
// error pending; the caller reads it once with takeError(), typed {code, message, path}
// (web/typed_output.js). Nothing throws across the boundary, so bad input never aborts the module
// and the next call works. An entry point that returns typed values returns their length and
// leaves them in the typed result (typedResult() is where they are) until the next such call.
#pragma once

#include <cstdint>
#include <exception>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "springbones/boundary.h"
#include "springbones/springbones.h"

namespace springbones::bindings {

// Its code is the core's errorCodeName(), one of boundary.h's argument codes, or one that only
// exists at the boundary: "out-of-memory", "internal-error", "bad-handle".
inline ApiFailure g_error;
inline std::vector<std::uint8_t> g_result;

/// Keeps `bytes` as the typed result; returns their length.
inline int result(std::vector<std::uint8_t> bytes) {
  g_result = std::move(bytes);
  return static_cast<int>(g_result.size());
}

inline std::uintptr_t typedResult() { return reinterpret_cast<std::uintptr_t>(g_result.data()); }

inline int fail(ApiFailure failure) {
  g_error = std::move(failure);
  return 0;
}
inline int fail(std::string code, std::string message) {
  return fail(ApiFailure{std::move(code), std::move(message), ""});
}
inline int fail(const Error& error) { return fail(toFailure(error)); }

/// Runs body, turning any C++ exception into the pending error. Returns body's result or 0.
template <typename Body>
int guarded(Body&& body) {
  try {
    return body();
  } catch (const std::bad_alloc&) { return fail("out-of-memory", "out of memory"); } catch (const std::exception& ex) {
    return fail("internal-error", std::string("internal error: ") + ex.what());
  } catch (...) { return fail("internal-error", "internal error"); }
}

/// The pending error as the typed result, then clears it; its length, or -1 when there was no
/// memory to write it (the JavaScript then reports "out-of-memory").
inline int takeError() {
  try {
    const int length = result(describeFailure(g_error));
    g_error = ApiFailure{};
    return length;
  } catch (...) { return -1; }
}

}  // namespace springbones::bindings
