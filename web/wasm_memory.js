// A module's WebAssembly memory from JavaScript: bytes and text copied in for the duration of one
// call, and when a view on it has to be made again.

import { SpringBonesError, call } from './errors.js';

// malloc, with a full heap as an out-of-memory error rather than a null pointer.
function allocate(m, size) {
  const ptr = m._malloc(size);
  if (ptr === 0) throw new SpringBonesError('out-of-memory', `could not allocate ${size} bytes in WebAssembly memory`);
  return ptr;
}

// Copies bytes into WASM memory for the duration of fn(ptr, size).
export function withBytes(m, bytes, fn) {
  const ptr = allocate(m, Math.max(1, bytes.length));
  try {
    m.HEAPU8.set(bytes, ptr);  // read HEAPU8 after malloc: it may have grown the memory
    return call(() => fn(ptr, bytes.length));
  } finally {
    m._free(ptr);
  }
}

// For the creator tools, whose bindings are embind's (the runtime's strings cross with withBytes:
// runtime_calls.js). embind copies each string argument into WASM memory with a malloc whose
// result it does not check: on a full heap it would write the text through a null pointer, over
// the module's static data. So the room for them (UTF-8 size plus embind's length word and terminator) is taken and
// given back first, and a full heap is an out-of-memory error before anything crosses. embind's
// mallocs then follow at once, in the same order, into the room just freed.
export function withRoomForStrings(m, texts, fn) {
  const taken = [];
  try {
    for (const text of texts) {
      taken.push(allocate(m, utf8Length(text) + 5));
    }
  } finally {
    for (let i = taken.length - 1; i >= 0; i--) m._free(taken[i]);
  }
  return fn();
}

// The UTF-8 size of a string as embind writes it (a lone surrogate as 3 bytes).
function utf8Length(text) {
  let size = text.length;
  for (let i = 0; i < text.length; i++) {
    const c = text.charCodeAt(i);
    if (c >= 0xd800 && c <= 0xdbff && i + 1 < text.length) {
      const d = text.charCodeAt(i + 1);
      if (d >= 0xdc00 && d <= 0xdfff) {
        size += 2;  // 4 bytes for 2 units
        i++;
        continue;
      }
    }
    if (c >= 0x800) size += 2;
    else if (c >= 0x80) size += 1;
  }
  return size;
}

/**
 * Whether a view of `length` elements on the module's memory has to be made again: memory growth
 * replaces the ArrayBuffer and detaches every view on the old one, which drops its length to 0.
 * Comparing lengths is what the per-frame getters can afford (TypedArray.prototype.buffer is a
 * runtime call in V8, ~35 ns); only an empty view needs the buffer compared.
 */
export function isStale(m, view, length) {
  return view.length !== length || (length === 0 && view.buffer !== m.HEAPU8.buffer);
}
