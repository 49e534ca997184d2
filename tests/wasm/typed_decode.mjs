// The typed encoding (web/typed_value.js, src/common/typed_value.h) read back into a JavaScript
// value, for tests that compare what two front ends hand the runtime. Objects come back with their
// members in byte order of their keys, as the core reads them.
import { kTypedTags as kTag } from '../../web/typed_encoding.js';

export function decodeTyped(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const decoder = new TextDecoder('utf-8', { fatal: true });
  let at = 0;
  const u32 = () => {
    const v = view.getUint32(at, true);
    at += 4;
    return v;
  };
  const text = () => {
    const length = u32();
    const s = decoder.decode(bytes.subarray(at, at + length));
    at += length;
    return s;
  };
  // Iterative, as the core's decoder is: [container, remaining, pending key].
  const open = [];
  let root;
  const place = (value) => {
    if (open.length === 0) {
      root = value;
      return;
    }
    const top = open[open.length - 1];
    if (Array.isArray(top.container)) top.container.push(value);
    else top.container[top.key] = value;
    top.remaining -= 1;
  };
  do {
    const top = open[open.length - 1];
    if (top && !Array.isArray(top.container)) top.key = text();
    const tag = bytes[at++];
    let value;
    if (tag === kTag.null) value = null;
    else if (tag === kTag.false) value = false;
    else if (tag === kTag.true) value = true;
    else if (tag === kTag.number) {
      value = view.getFloat64(at, true);
      at += 8;
    } else if (tag === kTag.string) value = text();
    else if (tag === kTag.array || tag === kTag.object) {
      const count = u32();
      value = tag === kTag.array ? [] : {};
      place(value);
      open.push({ container: value, remaining: count, key: undefined });
      while (open.length > 0 && open[open.length - 1].remaining === 0) open.pop();
      continue;
    } else throw new Error(`unknown tag ${tag} at ${at - 1}`);
    place(value);
    while (open.length > 0 && open[open.length - 1].remaining === 0) open.pop();
  } while (open.length > 0);
  if (at !== bytes.length) throw new Error(`${bytes.length - at} bytes after the value`);
  return sortKeys(root);
}

function sortKeys(value) {
  if (Array.isArray(value)) return value.map(sortKeys);
  if (value === null || typeof value !== 'object') return value;
  const out = {};
  for (const key of Object.keys(value).sort(byBytes)) out[key] = sortKeys(value[key]);
  return out;
}

const encoder = new TextEncoder();
function byBytes(a, b) {
  const x = encoder.encode(a);
  const y = encoder.encode(b);
  for (let i = 0; i < Math.min(x.length, y.length); ++i) if (x[i] !== y[i]) return x[i] - y[i];
  return x.length - y.length;
}
