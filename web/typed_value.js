// Typed input: a value the page already parsed (the glTF JSON its loader read, the entity that
// holds data.springBones), written in the binary encoding the core reads (src/common/typed_value.h
// has it; docs/design.md, "Typed input"), so that no JSON text crosses into WebAssembly and the
// core never parses one. Each value keeps its JSON type (null, boolean, number, string, array,
// object), so a stiffness given as a string still earns the core's warning and default.
//
// The value is seen as JSON.stringify sees it: toJSON() is called, members that are undefined,
// functions or symbols are left out of objects (functions and symbols become null in arrays),
// boxed primitives are unwrapped, and a cycle or a BigInt is a TypeError. What differs, on
// purpose: non-finite numbers stay numbers (the core names them, where JSON would turn them into
// null), a hole or an undefined element of an array is a TypeError (not a silent null), and a
// string that is not well-formed Unicode (a lone surrogate) is a RangeError rather than a silent
// U+FFFD.
// Iterative: a value nested any depth is written without recursion.

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

  // A u32 byte length, then the UTF-8 bytes (at most 3 per UTF-16 unit).
  sized(what, where, s) {
    if (!s.isWellFormed()) {
      throw new RangeError(`${what}: the string ${where()} has a lone surrogate (not well-formed Unicode)`);
    }
    this.room(4 + 3 * s.length);
    const { written } = encoder.encodeInto(s, this.bytes.subarray(this.length + 4));
    this.view.setUint32(this.length, written, true);
    this.length += 4 + written;
  }

  result() {
    return this.bytes.subarray(0, this.length);
  }
}

function describePath(keys) {
  return keys.length === 0 ? 'at the top' : `at ${keys.map((k) => JSON.stringify(String(k))).join(' > ')}`;
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
  const where = () => describePath(open.map((frame) => frame.key));
  const write = (v) => {
    if (v === null) {
      w.tag(kNull);
    } else if (typeof v === 'boolean') {
      w.tag(v ? kTrue : kFalse);
    } else if (typeof v === 'number') {
      w.number(v);
    } else if (typeof v === 'string') {
      w.tag(kString);
      w.sized(what, where, v);
    } else if (typeof v === 'bigint') {
      throw new TypeError(`${what}: a BigInt ${where()} has no JSON value`);
    } else {
      if (onPath.has(v)) throw new TypeError(`${what}: the value is circular ${where()}`);
      const isArray = Array.isArray(v);
      const children = [];
      if (isArray) {
        for (let i = 0; i < v.length; ++i) {
          if (!(i in v) || v[i] === undefined) {
            throw new TypeError(`${what}: ${i in v ? 'an undefined element' : 'a hole'} at index ${i} ${where()}`);
          }
          children.push([i, jsonValue(v[i], String(i)) ?? null]);
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
    if (!frame.isArray) w.sized(what, where, key);
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
