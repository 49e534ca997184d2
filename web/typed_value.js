// Typed input: a value the page already parsed (the glTF JSON its loader read, the entity that
// holds data.springBones), written in the binary encoding the core reads (src/common/typed_value.h
// has it; docs/design.md, "Typed input"), so that no JSON text crosses into WebAssembly and the
// core never parses one. Each value keeps its JSON type (null, boolean, number, string, array,
// object), so a stiffness given as a string still earns the core's warning and default.
//
// The value is seen as JSON.stringify sees it: toJSON() is called, members that are undefined,
// functions or symbols are left out of objects, boxed primitives are unwrapped, and a cycle or a
// BigInt is a TypeError. What JSON.stringify would change silently is refused, as arguments.js
// refuses it for the JSON the creator tools take: a hole or an undefined, function or symbol
// element of an array, and a typed array, are TypeErrors; a string or key with a lone surrogate
// is a RangeError (UTF-8 cannot encode it). Non-finite numbers stay numbers: the core names them
// (param-not-finite), where JSON would have turned them into null.
//
// Bounded by its input: every bound of typed_encoding.js (the core holds the same ones) is checked
// before the work it bounds, and exceeding one is a SpringBonesError 'limit-exceeded' naming the
// limit and the path. An array's length is read once, before its elements, so an array or Proxy
// that grows while it is read is written as long as it was; an object's keys are listed once.
// Iterative: a value nested any depth is written without recursion.

import { checkWellFormed } from './arguments.js';
import { SpringBonesError } from './errors.js';
import { kGltfNodeFields, kGltfRootExtensions, kTypedLimits, kTypedTags } from './typed_encoding.js';

const encoder = new TextEncoder();

/** A name from the input as a message quotes it: at most maxNameBytesInMessage UTF-16 units. */
export function shownName(name) {
  const max = kTypedLimits.maxNameBytesInMessage;
  if (name.length <= max) return name;
  let cut = max;
  const c = name.charCodeAt(cut - 1);
  if (c >= 0xd800 && c <= 0xdbff) --cut;  // not half of a pair
  return `${name.slice(0, cut)}...`;
}

/**
 * A string argument that goes beside typed input (a content hash, a body shape), held to the bound
 * of a typed string before it is copied anywhere: limit-exceeded past maxStringBytes of UTF-8.
 */
export function checkStringBound(what, s) {
  const max = kTypedLimits.maxStringBytes;
  if (s.length > max || (3 * s.length > max && encoder.encode(s).length > max)) {
    throw new SpringBonesError('limit-exceeded', `${what} is more than the limit of ${max} bytes for a string ` +
                               `(${s.length} UTF-16 units)`);
  }
  return s;
}

function limitExceeded(message, steps) {
  return new SpringBonesError('limit-exceeded', message, steps.map(({ key }) => `/${shownName(String(key))
    .replaceAll('~', '~0').replaceAll('/', '~1')}`).join(''));
}

class Writer {
  constructor(maxBytes) {
    this.maxBytes = maxBytes;
    this.bytes = new Uint8Array(256);
    this.view = new DataView(this.bytes.buffer);
    this.length = 0;
  }

  // `n` more bytes, refused past maxBytes before the buffer grows.
  room(n, steps) {
    if (this.length + n <= this.bytes.length) return;
    if (this.length + n > this.maxBytes) throw this.tooLarge(this.length + n, steps);
    let size = this.bytes.length * 2;
    while (size < this.length + n) size *= 2;
    const bigger = new Uint8Array(Math.min(size, this.maxBytes));
    bigger.set(this.bytes.subarray(0, this.length));
    this.bytes = bigger;
    this.view = new DataView(bigger.buffer);
  }

  tooLarge(bytes, steps) {
    return limitExceeded(`${this.what} is more than the limit of ${this.maxBytes} bytes as typed input ` +
                         `(${bytes} or more)`, steps);
  }

  tag(t, steps) {
    this.room(1, steps);
    this.bytes[this.length++] = t;
  }

  u32(v, steps) {
    this.room(4, steps);
    this.view.setUint32(this.length, v, true);
    this.length += 4;
  }

  number(v, steps) {
    this.tag(kTypedTags.number, steps);
    this.room(8, steps);
    this.view.setFloat64(this.length, v, true);
    this.length += 8;
  }

  // A u32 byte length, then the UTF-8 bytes (at most 3 per UTF-16 unit), refused past
  // maxStringBytes before any is encoded. `name()` names the string for an error.
  sized(name, s, steps) {
    const max = kTypedLimits.maxStringBytes;
    const tooLong = () => limitExceeded(`${name()} is more than the limit of ${max} bytes for a string or a key ` +
                                        `(${s.length} UTF-16 units)`, steps);
    if (s.length > max) throw tooLong();
    if (!s.isWellFormed()) checkWellFormed(name(), s);
    let most = Math.min(3 * s.length, max);
    // Near the end of the input's bound, the exact length: the worst case must not refuse a fit.
    if (this.length + 4 + most > this.maxBytes) most = Math.min(encoder.encode(s).length, max + 1);
    this.room(4 + most, steps);
    const { read, written } = encoder.encodeInto(s, this.bytes.subarray(this.length + 4, this.length + 4 + most));
    if (read < s.length) throw tooLong();
    this.view.setUint32(this.length, written, true);
    this.length += 4 + written;
  }

  result() {
    return this.bytes.subarray(0, this.length);
  }
}

// The path of a value from the argument, as JavaScript would write it (`.key`, `["odd key"]`,
// `[index]`), as arguments.js spells it; a key is quoted by its bounded prefix.
function pathOf(what, steps) {
  let path = what;
  for (const { key, isArray } of steps) {
    const k = isArray ? key : shownName(key);
    path += isArray ? `[${k}]` : /^[A-Za-z_$][\w$]*$/.test(k) ? `.${k}` : `[${JSON.stringify(k)}]`;
  }
  return path;
}

// The value JSON.stringify would write for `value` under `key`, or undefined where it writes none.
function jsonValue(value, key) {
  if ((typeof value === 'object' && value !== null) || typeof value === 'bigint') {
    if (typeof value.toJSON === 'function') value = value.toJSON(key);
  }
  if (value instanceof Number || value instanceof String || value instanceof Boolean) value = value.valueOf();
  if (value === undefined || typeof value === 'function' || typeof value === 'symbol') return undefined;
  return value;
}

/**
 * The typed encoding of `value` (which must be JSON-like), as a Uint8Array.
 * @param {string} what the argument, for error messages ("loadRig: springBones")
 * @param {number} [maxBytes] the bound of the whole input (typed_encoding.js: maxMetadataTypedBytes
 *   for springBones, an entity or options; maxGltfTypedBytes for a glTF document)
 */
export function encodeTyped(what, value, maxBytes = kTypedLimits.maxMetadataTypedBytes) {
  const w = new Writer(maxBytes);
  w.what = what;
  const onPath = new Set();
  // Open containers: their children ([key, value] pairs) and the one being written.
  const open = [];
  const here = () => pathOf(what, open);
  let values = 0;
  const write = (v) => {
    if (++values > kTypedLimits.maxValues) {
      throw limitExceeded(`${what} holds more than the limit of ${kTypedLimits.maxValues} values (at ${here()})`, open);
    }
    if (v === null) {
      w.tag(kTypedTags.null, open);
    } else if (typeof v === 'boolean') {
      w.tag(v ? kTypedTags.true : kTypedTags.false, open);
    } else if (typeof v === 'number') {
      w.number(v, open);
    } else if (typeof v === 'string') {
      w.tag(kTypedTags.string, open);
      w.sized(here, v, open);
    } else if (typeof v === 'bigint') {
      throw new TypeError(`${here()} is a BigInt, which JSON cannot hold`);
    } else {
      if (onPath.has(v)) throw new TypeError(`${here()} is circular: it contains itself`);
      if (ArrayBuffer.isView(v)) throw new TypeError(`${here()} is a ${v.constructor?.name ?? 'typed array'}: give a plain array`);
      const isArray = Array.isArray(v);
      const tooMany = (count) => limitExceeded(`${here()} has ${count} ${isArray ? 'elements' : 'members'}, more ` +
                                               `than the limit of ${kTypedLimits.maxContainerSize}`, open);
      const children = [];
      if (isArray) {
        const length = v.length;  // once: an array that grows while it is read is written as it was
        if (!(length <= kTypedLimits.maxContainerSize)) throw tooMany(length);
        for (let i = 0; i < length; ++i) {
          const at = () => `${here()}[${i}]`;
          if (!(i in v)) throw new TypeError(`${at()} is a hole (a sparse array); give every element`);
          const element = v[i];
          const child = jsonValue(element, String(i));
          if (child === undefined) {
            throw new TypeError(`${at()} is ${element === undefined ? 'undefined' : `a ${typeof element}`}, which JSON cannot hold`);
          }
          children.push([i, child]);
        }
      } else {
        const keys = Object.keys(v);
        if (keys.length > kTypedLimits.maxContainerSize) throw tooMany(keys.length);
        for (const key of keys) {
          const child = jsonValue(v[key], key);
          if (child !== undefined) children.push([key, child]);
        }
      }
      w.tag(isArray ? kTypedTags.array : kTypedTags.object, open);
      w.u32(children.length, open);
      onPath.add(v);
      open.push({ value: v, children, next: 0, isArray, key: undefined });
    }
  };
  const top = jsonValue(value, '');
  write(top === undefined ? null : top);
  while (open.length > 0) {
    const frame = open[open.length - 1];
    if (frame.next === frame.children.length) {
      onPath.delete(frame.value);
      open.pop();
      continue;
    }
    const [key, child] = frame.children[frame.next++];
    frame.key = key;
    if (!frame.isArray) w.sized(() => `${here()}: its key`, key, open);
    write(child);
  }
  return w.result();
}

const isObject = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);

// A member the runtime reads only for its type: a container by its kind alone and a string empty,
// so that what is inside is neither copied nor checked; other scalars as they are.
const shapeOnly = (v) => (Array.isArray(v) ? [] : isObject(v) ? {} : typeof v === 'string' ? '' : v);

// The members of a glTF document the core reads (typed_encoding.json, "gltf"): asset.version, the
// nodes' fields and, for a VRM, the root extensions it reads (a node's meshes, skins and extras,
// and every other extension, are never copied). What the core refuses (a node that is not an
// object...) is written as null, which it refuses in the same words; the readers module
// (src/readers/readers.cpp) keeps the same members of a file. The node count is read once and
// checked against maxNodes before any node is.
function gltfPart(what, gltf, withExtensions) {
  const part = {};
  const { asset, nodes } = gltf;
  if (asset !== undefined) part.asset = !isObject(asset) ? null : asset.version === undefined ? {} : { version: asset.version };
  if (nodes !== undefined) {
    if (!Array.isArray(nodes)) {
      part.nodes = null;
    } else {
      const count = nodes.length;
      if (!(count <= kTypedLimits.maxNodes)) {
        throw new SpringBonesError('limit-exceeded', `${what}.nodes has ${count} nodes, more than the limit of ` +
                                   `${kTypedLimits.maxNodes}`, '/nodes');
      }
      part.nodes = new Array(count);
      for (let i = 0; i < count; ++i) {
        if (!(i in nodes)) throw new TypeError(`${what}.nodes[${i}] is a hole (a sparse array); give every element`);
        const node = nodes[i];
        if (!isObject(node)) {
          part.nodes[i] = null;
          continue;
        }
        const fields = {};
        for (const key of kGltfNodeFields) {
          const field = node[key];
          if (field !== undefined) fields[key] = field;
        }
        part.nodes[i] = fields;
      }
    }
  }
  if (withExtensions && gltf.extensions !== undefined) part.extensions = rootExtensions(gltf.extensions);
  return part;
}

function rootExtensions(extensions) {
  if (!isObject(extensions)) return shapeOnly(extensions);
  const out = {};
  for (const [name, members] of Object.entries(kGltfRootExtensions)) {
    const extension = extensions[name];
    if (extension === undefined) continue;
    if (members === 'all' || !isObject(extension)) {
      out[name] = members === 'all' ? extension : shapeOnly(extension);
      continue;
    }
    const kept = {};
    for (const member of members) if (extension[member] !== undefined) kept[member] = extension[member];
    out[name] = kept;
  }
  return out;
}

/** The typed input of a parsed glTF document: what gltfPart keeps of it. */
export function encodeGltf(what, gltf, withExtensions) {
  return encodeTyped(what, gltfPart(what, gltf, withExtensions), kTypedLimits.maxGltfTypedBytes);
}
