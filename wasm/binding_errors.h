// What every bindings file of a module shares (wasm/bindings.cpp for the runtime module,
// wasm/creator_tools_bindings.cpp for the creator tools): the pending error and the guard that
// turns any C++ exception into one. Each module is its own WebAssembly instance with its own
// memory, so each has its own pending error; `inline` keeps one per module however many files
// include this.
//
// Contract with the JavaScript side: an entry point that fails returns 0 (or "") and leaves the
// error pending; the caller reads it once with takeError() as JSON {code, message, path}. Nothing
// throws across the boundary, so bad input never aborts the module and the next call works.
#pragma once

#include <exception>
#include <new>
#include <string>
#include <utility>

#include "springbones/boundary.h"
#include "springbones/springbones.h"

namespace springbones::bindings {

// Its code is the core's errorCodeName(), one of boundary.h's argument codes, or one that only
// exists at the boundary: "out-of-memory", "internal-error", "bad-handle".
inline ApiFailure g_error;

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

/// The pending error as JSON {code, message, path}, then clears it.
inline std::string takeError() {
  try {
    const std::string text = failureJson(g_error);
    g_error = ApiFailure{};
    return text;
  } catch (...) { return R"({"code":"out-of-memory","message":"out of memory","path":""})"; }
}

}  // namespace springbones::bindings
