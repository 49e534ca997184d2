// malloc, free, realloc, calloc and the aligned allocations over Emscripten's allocator, each block
// carrying the size it was asked for, so that stats().heapInUse is the bytes requested and not
// freed: the same after two identical loads, and back to its value after a dispose, whatever the
// allocator rounds a block up to or how it splits its free regions. The allocator's own count
// (mallinfo) is of its regions, and depends on their layout: emmalloc hands a used region the
// slack of the free region it was split from, so two identical warm-ups in a row left it 8 bytes
// apart (docs/performance.md, "The allocator").
//
// Emscripten's allocators (dlmalloc and emmalloc alike) define these names weakly so that a program
// can replace them, and export themselves as emscripten_builtin_* for the replacement to call, as
// the sanitizers do. So every caller in the module comes through here: operator new
// (src/common/memory_reserve.cpp), libc and libc++abi (exceptions take an aligned allocation),
// the creator tools' embind strings and the JavaScript API's _malloc/_free (the runtime's string
// arguments and bytes). The few libc internals that allocate
// under the allocator's own names (emscripten_builtin_malloc, musl's __libc_malloc: the atexit
// table, locales) free under those names too, never through here, and are not counted.
#include "heap_in_use.h"

#include <emscripten/emmalloc.h>  // declares emscripten_builtin_*, which dlmalloc defines too

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstring>

extern "C" void* __libc_realloc(void* block, std::size_t size);  // the allocator's realloc

namespace {

// Before each block handed out. Its size keeps the blocks at malloc's alignment.
struct BlockHeader {
  std::size_t requested;  // what the caller asked for, what heapInUse counts
  std::size_t offset;     // from the allocator's block to the caller's: the header's size or an alignment
};
constexpr std::size_t kHeaderBytes = sizeof(BlockHeader);
static_assert(kHeaderBytes == alignof(std::max_align_t), "blocks keep malloc's alignment");

std::size_t g_in_use = 0;

BlockHeader* headerOf(void* p) { return static_cast<BlockHeader*>(p) - 1; }

// The caller's block `offset` bytes into the allocator's `block` (null when it failed), counted.
void* handOut(void* block, std::size_t offset, std::size_t requested) {
  if (block == nullptr) return nullptr;
  void* p = static_cast<char*>(block) + offset;
  *headerOf(p) = {requested, offset};
  g_in_use += requested;
  return p;
}

void* failOutOfMemory() {
  errno = ENOMEM;
  return nullptr;
}

bool isPowerOfTwo(std::size_t n) { return n != 0 && (n & (n - 1)) == 0; }

}  // namespace

extern "C" {

void* malloc(std::size_t size) {
  if (size > SIZE_MAX - kHeaderBytes) return failOutOfMemory();
  return handOut(emscripten_builtin_malloc(size + kHeaderBytes), kHeaderBytes, size);
}

void free(void* p) {
  if (p == nullptr) return;
  const BlockHeader header = *headerOf(p);
  g_in_use -= header.requested;
  emscripten_builtin_free(static_cast<char*>(p) - header.offset);
}

void* calloc(std::size_t count, std::size_t size) {
  if (size != 0 && count > SIZE_MAX / size) return failOutOfMemory();
  void* p = malloc(count * size);
  if (p != nullptr) std::memset(p, 0, count * size);
  return p;
}

void* realloc(void* p, std::size_t size) {
  if (p == nullptr) return malloc(size);
  const BlockHeader header = *headerOf(p);
  if (header.offset != kHeaderBytes) {
    // An aligned block: the allocator's realloc would not keep its alignment.
    void* moved = malloc(size);
    if (moved == nullptr) return nullptr;
    std::memcpy(moved, p, std::min(size, header.requested));
    free(p);
    return moved;
  }
  if (size > SIZE_MAX - kHeaderBytes) return failOutOfMemory();
  void* block = __libc_realloc(static_cast<char*>(p) - kHeaderBytes, size + kHeaderBytes);
  if (block == nullptr) return nullptr;  // the old block stays, and its count
  g_in_use -= header.requested;
  return handOut(block, kHeaderBytes, size);
}

void* memalign(std::size_t alignment, std::size_t size) {
  if (!isPowerOfTwo(alignment)) {
    errno = EINVAL;
    return nullptr;
  }
  if (alignment <= kHeaderBytes) return malloc(size);
  // The caller's block starts one alignment in, so the header fits before it.
  if (size > SIZE_MAX - alignment) return failOutOfMemory();
  return handOut(emscripten_builtin_memalign(alignment, size + alignment), alignment, size);
}

void* aligned_alloc(std::size_t alignment, std::size_t size) { return memalign(alignment, size); }

int posix_memalign(void** out, std::size_t alignment, std::size_t size) {
  if (alignment % sizeof(void*) != 0 || !isPowerOfTwo(alignment)) return EINVAL;
  void* p = memalign(alignment, size);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}

// The caller may use what it asked for, no more: the allocator's slack is not its to use.
std::size_t malloc_usable_size(void* p) { return p == nullptr ? 0 : headerOf(p)->requested; }

}  // extern "C"

std::size_t springbones::bindings::heapInUse() { return g_in_use; }
