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
// Iterative: a value nested any depth is written without recursion.

import { checkWellFormed } from './arguments.js';

const kNull = 0, kFalse = 1, kTrue = 2, kNumber = 3, kString = 4, kArray = 5, kObject = 6;
const encoder = new TextEncoder();

class Writer {
  constructor() {
    this.bytes = new Uint8Array(256);
    this.view = new DataView(this.bytes.buffer);
    this.length = 0;
  }

  room(n) {
    if (this.length + n <= this.bytes.length) return;
    let size = this.bytes.length * 2;
    while (size < this.length + n) size *= 2;
    const bigger = new Uint8Array(size);
    bigger.set(this.bytes.subarray(0, this.length));
    this.bytes = bigger;
    this.view = new DataView(bigger.buffer);
  }

  tag(t) {
    this.room(1);
    this.bytes[this.length++] = t;
  }

  u32(v) {
    this.room(4);
    this.view.setUint32(this.length, v, true);
    this.length += 4;
  }

  number(v) {
    this.tag(kNumber);
    this.room(8);
    this.view.setFloat64(this.length, v, true);
    this.length += 8;
  }

  // A u32 byte length, then the UTF-8 bytes (at most 3 per UTF-16 unit). `name()` names the string
  // for the RangeError of a lone surrogate, which UTF-8 cannot encode (arguments.js).
  sized(name, s) {
    if (!s.isWellFormed()) checkWellFormed(name(), s);
    this.room(4 + 3 * s.length);
    const { written } = encoder.encodeInto(s, this.bytes.subarray(this.length + 4));
    this.view.setUint32(this.length, written, true);
    this.length += 4 + written;
  }

  result() {
    return this.bytes.subarray(0, this.length);
  }
}

// The path of a value from the argument, as JavaScript would write it (`.key`, `["odd key"]`,
// `[index]`), as arguments.js spells it.
function pathOf(what, steps) {
  let path = what;
  for (const { key, isArray } of steps) {
    path += isArray ? `[${key}]` : /^[A-Za-z_$][\w$]*$/.test(key) ? `.${key}` : `[${JSON.stringify(key)}]`;
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
 */
export function encodeTyped(what, value) {
  const w = new Writer();
  const onPath = new Set();
  // Open containers: their children ([key, value] pairs) and the one being written.
  const open = [];
  const here = () => pathOf(what, open);
  const write = (v) => {
    if (v === null) {
      w.tag(kNull);
    } else if (typeof v === 'boolean') {
      w.tag(v ? kTrue : kFalse);
    } else if (typeof v === 'number') {
      w.number(v);
    } else if (typeof v === 'string') {
      w.tag(kString);
      w.sized(here, v);
    } else if (typeof v === 'bigint') {
      throw new TypeError(`${here()} is a BigInt, which JSON cannot hold`);
    } else {
      if (onPath.has(v)) throw new TypeError(`${here()} is circular: it contains itself`);
      if (ArrayBuffer.isView(v)) throw new TypeError(`${here()} is a ${v.constructor?.name ?? 'typed array'}: give a plain array`);
      const isArray = Array.isArray(v);
      const children = [];
      if (isArray) {
        for (let i = 0; i < v.length; ++i) {
          const at = () => `${here()}[${i}]`;
          if (!(i in v)) throw new TypeError(`${at()} is a hole (a sparse array); give every element`);
          const child = jsonValue(v[i], String(i));
          if (child === undefined) {
            throw new TypeError(`${at()} is ${v[i] === undefined ? 'undefined' : `a ${typeof v[i]}`}, which JSON cannot hold`);
          }
          children.push([i, child]);
        }
      } else {
        for (const key of Object.keys(v)) {
          const child = jsonValue(v[key], key);
          if (child !== undefined) children.push([key, child]);
        }
      }
      w.tag(isArray ? kArray : kObject);
      w.u32(children.length);
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
    if (!frame.isArray) w.sized(() => `${here()}: its key`, key);
    write(child);
  }
  return w.result();
}

// The members of a glTF document the core reads: asset.version, the nodes' hierarchy fields and,
// for a VRM, the root extensions (a node's meshes, skins and extras are never copied). What the
// core refuses (a node that is not an object...) is written as null, which it refuses in the same
// words; the readers module (src/readers/readers.cpp) keeps the same members of a file.
const kNodeFields = ['name', 'children', 'translation', 'rotation', 'scale', 'matrix'];
function gltfPart(gltf, withExtensions) {
  const isObject = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);
  const part = {};
  const { asset, nodes } = gltf;
  if (asset !== undefined) part.asset = !isObject(asset) ? null : asset.version === undefined ? {} : { version: asset.version };
  if (nodes !== undefined) {
    part.nodes = !Array.isArray(nodes) ? null : nodes.map((node) => {
      if (!isObject(node)) return null;
      const fields = {};
      for (const key of kNodeFields) if (node[key] !== undefined) fields[key] = node[key];
      return fields;
    });
  }
  if (withExtensions && gltf.extensions !== undefined) part.extensions = gltf.extensions;
  return part;
}

/** The typed input of a parsed glTF document: what gltfPart keeps of it. */
export function encodeGltf(what, gltf, withExtensions) {
  return encodeTyped(what, gltfPart(gltf, withExtensions));
}
