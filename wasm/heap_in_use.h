// The heap in use that a module's stats() reports (heapInUse): the bytes the program has asked
// malloc and its kin for and not freed, counted by wasm/heap_in_use.cpp, which every module with a
// stats() links (wasm/CMakeLists.txt).
#pragma once

#include <cstddef>

namespace springbones::bindings {

std::size_t heapInUse();

}  // namespace springbones::bindings
