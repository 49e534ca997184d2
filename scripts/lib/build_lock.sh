# shellcheck shell=bash
# Sourced by the scripts that build (scripts/build, scripts/test, scripts/fuzz, scripts/bench).
#
#   with_build_lock NAME COMMAND...   runs COMMAND holding build/NAME.lock of this checkout
#
# One lock per build folder of one checkout (NAME is the preset, build/NAME/ what it guards), so
# a second checkout never waits for the first, and in one checkout the fuzz build does not wait for
# the WebAssembly one. What the checkouts share, the compiler cache, takes its own locks.
#
# The holder writes a note into the lock file (pid, since when, what it runs); a script that has
# to wait prints it, with how to go on, and prints it again every minute it still waits.
# SPRINGBONES_BUILD_LOCK_WAIT=<seconds> bounds the wait (0: fail at once when the lock is held);
# unset, a script waits as long as it takes.

build_lock_note() {
  local lock="$1" pid since command
  pid=$(sed -n 's/^pid=//p' "$lock" 2>/dev/null)
  since=$(sed -n 's/^since=//p' "$lock" 2>/dev/null)
  command=$(sed -n 's/^command=//p' "$lock" 2>/dev/null)
  if [ -z "$pid" ]; then
    echo "$lock is held by a process that left no note (a build of an older script?); 'fuser -v $lock' names it"
    return
  fi
  local age=""
  [ -n "$since" ] && age=" since $(date -u -d "@$since" '+%H:%M:%S UTC') ($(( $(date +%s) - since )) s ago)"
  echo "$lock is held by pid $pid${age}: $command"
}

with_build_lock() {
  local name="$1"
  shift
  local limit="${SPRINGBONES_BUILD_LOCK_WAIT:-}"
  if ! [[ "$limit" =~ ^[0-9]*$ ]]; then
    echo "SPRINGBONES_BUILD_LOCK_WAIT=$limit: expected a number of seconds (0: do not wait)" >&2
    return 2
  fi
  mkdir -p build
  local lock="build/$name.lock" fd
  exec {fd}>>"$lock"
  if ! flock -n "$fd"; then
    echo "build lock: $(build_lock_note "$lock")" >&2
    if [ "$limit" = 0 ]; then
      echo "build lock: not waiting (SPRINGBONES_BUILD_LOCK_WAIT=0); run again when it is free" >&2
      exec {fd}>&-
      return 75
    fi
    echo "build lock: waiting${limit:+ up to $limit s} (SPRINGBONES_BUILD_LOCK_WAIT=<seconds> bounds the wait," \
      "0 fails at once; or stop that process if it is stuck)" >&2
    local waited=0 step
    while true; do
      step=60
      [ -n "$limit" ] && [ $((limit - waited)) -lt $step ] && step=$((limit - waited))
      flock -w "$step" "$fd" && break
      waited=$((waited + step))
      if [ -n "$limit" ] && [ "$waited" -ge "$limit" ]; then
        echo "build lock: gave up after $waited s: $(build_lock_note "$lock")" >&2
        exec {fd}>&-
        return 75
      fi
      echo "build lock: still waiting after $waited s: $(build_lock_note "$lock")" >&2
    done
  fi
  printf 'pid=%s\nsince=%s\ncommand=%s\n' "$BASHPID" "$(date +%s)" "$0: $*" >"$lock"
  # Not `"$@" || status=$?`: that would turn off `set -e` inside a function given as COMMAND. Under
  # set -e a failure ends the script here, and the lock goes with its file descriptor.
  "$@"
  local status=$?
  : >"$lock"
  exec {fd}>&-
  return "$status"
}
