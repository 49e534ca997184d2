# shellcheck shell=bash
# Sourced by the scripts that build (scripts/build, scripts/test, scripts/fuzz, scripts/bench), from
# the checkout's root.
#
#   build_preset PRESET [TARGET...]   configures build/PRESET and builds it (every target by default)
#
# A build folder that came with a copied or moved tree holds a CMake cache naming the folder it was
# made in, and CMake refuses it ("The current CMakeCache.txt directory ... is different"). Such a
# folder is configured afresh in place, with one line that says so: the objects are compiled
# again, from the compiler cache when they were compiled before.

# Removes the CMake cache of build folder $1 when it was made for another folder or checkout.
forget_moved_cmake_cache() {
  local dir="$1"
  local cache="$dir/CMakeCache.txt"
  [ -f "$cache" ] || return 0
  local made_in home
  made_in=$(sed -n 's/^CMAKE_CACHEFILE_DIR:INTERNAL=//p' "$cache")
  home=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$cache")
  # -ef compares the folders themselves (device and inode), whatever symbolic links name them.
  if [ -n "$made_in" ] && [ "$made_in" -ef "$dir" ] && [ -n "$home" ] && [ "$home" -ef . ]; then
    return 0
  fi
  echo "$dir: its CMake cache was made in ${made_in:-another folder}; configuring it afresh here"
  rm -rf "$cache" "$dir/CMakeFiles"
}

build_preset() {
  local preset="$1"
  shift
  # Each step returns on failure: a caller's `if` turns `set -e` off in here.
  forget_moved_cmake_cache "build/$preset" || return
  cmake --preset "$preset" >/dev/null || return
  local targets=()
  [ $# -gt 0 ] && targets=(--target "$@")
  cmake --build --preset "$preset" -j "$(nproc)" "${targets[@]}"
}
