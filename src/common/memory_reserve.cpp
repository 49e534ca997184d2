// Running out of memory must end in std::bad_alloc reaching the bindings, never in std::terminate.
// In WebAssembly a full heap is a real state (the memory cannot grow past its maximum, or the
// engine cannot reserve more), and unwinding from the failed allocation needs memory of its own:
// the exception object, and nlohmann::json's destructor, which is noexcept and allocates a stack
// to tear nested values down (found with a capped memory: loadVrm on a full heap aborted the
// module from ~basic_json). So the first failed allocation hands back a reserve held for exactly
// that moment before throwing, and the reserve is taken again by the first allocation made with
// no exception in flight (the unwinding is over) once the heap has room for it.
//
// WebAssembly only: a native process does not run out this way (overcommit), and the sanitizers
// bring their own operator new.
#ifdef __EMSCRIPTEN__

#include <cstddef>
#include <cstdlib>
#include <exception>
#include <new>

namespace {

constexpr std::size_t kReserveBytes = 256 * 1024;
void* g_reserve = nullptr;

void takeReserve() {
  if (g_reserve == nullptr) g_reserve = std::malloc(kReserveBytes);
}

// Taken when the module starts rather than by the first allocation, so that the heap in use the
// leak checks compare does not jump by the reserve between two calls of a module.
[[maybe_unused]] const bool g_reserve_taken_at_start = (takeReserve(), true);

void* allocate(std::size_t size) {
  if (size == 0) size = 1;
  void* p = std::malloc(size);
  if (p != nullptr) {
    // Not while unwinding: the destructors still running may need the room it would take.
    if (g_reserve == nullptr && std::uncaught_exceptions() == 0) takeReserve();
    return p;
  }
  std::free(g_reserve);
  g_reserve = nullptr;
  throw std::bad_alloc();
}

}  // namespace

void* operator new(std::size_t size) { return allocate(size); }
void* operator new[](std::size_t size) { return allocate(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size);
  } catch (...) { return nullptr; }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size);
  } catch (...) { return nullptr; }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

#endif  // __EMSCRIPTEN__
