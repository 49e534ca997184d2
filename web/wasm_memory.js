// Bytes and text copied into a module's WebAssembly memory for the duration of one call.

import { SpringBonesError, call } from './errors.js';

const kTextEncoder = new TextEncoder();

// JSON text as UTF-8 bytes for the core. A lone surrogate (possible in a string, never in UTF-8)
// is written as its 3-byte WTF-8 form instead of TextEncoder's U+FFFD, so the core still sees
// text that is not UTF-8 and reports metadata-bad-json rather than reading a replaced name.
function utf8Bytes(text) {
  if (isWellFormed(text)) return kTextEncoder.encode(text);
  const out = [];
  for (const ch of text) {  // by code point: pairs stay together, lone surrogates come alone
    const cp = ch.codePointAt(0);
    if (cp >= 0xd800 && cp <= 0xdfff) {
      out.push(0xe0 | (cp >> 12), 0x80 | ((cp >> 6) & 0x3f), 0x80 | (cp & 0x3f));
    } else {
      out.push(...kTextEncoder.encode(ch));
    }
  }
  return Uint8Array.from(out);
}

// String.prototype.isWellFormed is recent (2023); the regex is the fallback for older engines.
function isWellFormed(text) {
  return typeof text.isWellFormed === 'function' ? text.isWellFormed() : !/\p{Cs}/u.test(text);
}

// Text as UTF-8 bytes in WASM memory for the duration of fn(ptr, size): encoded straight into
// the heap when it is well formed (no intermediate array), else through utf8Bytes.
export function withUtf8(m, text, fn) {
  if (!isWellFormed(text)) return withBytes(m, utf8Bytes(text), fn);
  const capacity = Math.max(1, 3 * text.length);  // UTF-8 takes at most 3 bytes per UTF-16 unit
  const ptr = allocate(m, capacity);
  try {
    const { written } = kTextEncoder.encodeInto(text, m.HEAPU8.subarray(ptr, ptr + capacity));
    return call(() => fn(ptr, written));
  } finally {
    m._free(ptr);
  }
}

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

// embind copies each string argument into WASM memory with a malloc whose result it does not
// check: on a full heap it would write the text through a null pointer, over the module's static
// data. So the room for them (UTF-8 size plus embind's length word and terminator) is taken and
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
