// Argument checks and serialization shared by the runtime API (springbones.js), the creator tools
// (creator_tools.js) and the module loader: everything here runs before a call crosses into
// WebAssembly.

import { SpringBonesError, withCause } from './errors.js';

export function checkKeys(where, object, allowed) {
  for (const key of Object.keys(object)) {
    if (!allowed.includes(key)) {
      throw new TypeError(`${where}: unknown option '${key}' (known: ${allowed.join(', ')})`);
    }
  }
}

export function optionsObject(where, options, allowed) {
  if (options === undefined || options === null) return {};
  if (typeof options !== 'object' || Array.isArray(options)) throw new TypeError(`${where}: options must be an object`);
  checkKeys(where, options, allowed);
  return options;
}

// The options that say which models entry applies (loadRig, detectSpringBones).
export const kHashOptions = ['contentHash', 'entity', 'bodyShape'];

export function checkNonEmptyString(what, value, described = 'a string') {
  if (typeof value !== 'string') throw new TypeError(`${what} must be ${described}`);
  if (value.length === 0) throw new RangeError(`${what} must not be empty`);
  return checkWellFormed(what, value);
}

// A string with a lone surrogate (half of a UTF-16 pair) has no UTF-8 form: TextEncoder would
// write U+FFFD in its place, so a name would be looked up, or saved, as another name. Every
// string that crosses into WebAssembly is refused instead, names, hashes and JSON text alike.
export function checkWellFormed(what, text) {
  if (!isWellFormed(text)) {
    const at = loneSurrogateIndex(text);
    throw new RangeError(`${what} contains a lone surrogate (U+${text.charCodeAt(at).toString(16).toUpperCase()} ` +
        `at index ${at}), which UTF-8 cannot encode`);
  }
  return text;
}

const isWellFormed = typeof String.prototype.isWellFormed === 'function'
  ? (text) => text.isWellFormed()
  : (text) => !/\p{Cs}/u.test(text);

function loneSurrogateIndex(text) {
  for (let i = 0; i < text.length; ++i) {
    const c = text.charCodeAt(i);
    if (c >= 0xd800 && c <= 0xdbff) {
      const next = text.charCodeAt(i + 1);
      if (next >= 0xdc00 && next <= 0xdfff) ++i;
      else return i;
    } else if (c >= 0xdc00 && c <= 0xdfff) {
      return i;
    }
  }
  return -1;
}

/**
 * An array argument with an element at every index: a hole (`[a, , b]`, `new Array(3)`) is a
 * TypeError, as an undefined element is, rather than skipped by map() or written as null. Returns
 * the elements as read, in a new array.
 */
export function checkDenseArray(what, array) {
  // The length and each element read once, into a copy: an array that grows as it is read is taken as it was.
  const out = new Array(array.length);
  for (let i = 0; i < out.length; ++i) {
    if (!(i in array)) throw new TypeError(`${what}[${i}] is a hole (a sparse array); give every element`);
    if ((out[i] = array[i]) === undefined) throw new TypeError(`${what}[${i}] is undefined`);
  }
  return out;
}

export function toBytes(what, value) {
  if (value instanceof Uint8Array) return value;
  if (value instanceof ArrayBuffer) return new Uint8Array(value);
  throw new TypeError(`${what} must be a Uint8Array or an ArrayBuffer`);
}

// Objects are serialised; strings are taken as JSON text (the core parses and reports errors);
// null/undefined is "no spring bones" where allowed. `options` as stringifyArgument's.
export function toJsonText(what, value, allowNull, options) {
  if (typeof value === 'string') return checkWellFormed(what, value);
  if (value === null || value === undefined) {
    if (allowNull) return 'null';
    throw new TypeError(`${what} must be an object or JSON text`);
  }
  if (typeof value !== 'object') {
    throw new TypeError(`${what} must be an object, JSON text${allowNull ? ', null or undefined' : ''}`);
  }
  return stringifyArgument(what, value, options);
}

// JSON.stringify of a caller's value, with what it would silently change refused first (checked
// on what each toJSON returns, as JSON.stringify writes that): an array's hole, or an undefined,
// function or symbol element (written as null), is a TypeError; so is a typed array or DataView
// (written as an object of its indices); a string or key with a lone surrogate is a RangeError
// (see checkWellFormed). `options.finite`: a NaN or an infinity (written as null) is a RangeError
// too. `options.replacer` then maps each value, as JSON.stringify's replacer.
//
// One nested too deeply for the engine's stack (thousands of levels: V8 and JavaScriptCore throw
// a RangeError, Firefox an InternalError) is an invalid argument, reported as the core reports
// params nested deeper than it edits, rather than an engine error escaping the API. Cycles and
// BigInt still throw JSON.stringify's TypeError, and an error thrown by a toJSON or a getter goes
// through as it is.
export function stringifyArgument(what, value, { finite = false, replacer } = {}) {
  // Where each object or array sits (its holder and key), for messages: filled as JSON.stringify
  // walks down; the path is spelled out only for an error.
  const parents = new WeakMap();
  const at = (holder, key) => `${what}${pathTo(parents, holder, key)}`;
  const check = function (key, v) {
    if (Array.isArray(this)) {
      if (!Object.hasOwn(this, key)) throw new TypeError(`${at(this, key)} is a hole (a sparse array); give every element`);
      if (v === undefined || typeof v === 'function' || typeof v === 'symbol') {
        throw new TypeError(`${at(this, key)} is ${v === undefined ? 'undefined' : `a ${typeof v}`}, which JSON cannot hold`);
      }
    } else if (!isWellFormed(key)) {
      checkWellFormed(`${at(this, key)}: its key`, key);
    }
    if (typeof v === 'string') {
      if (!isWellFormed(v)) checkWellFormed(at(this, key), v);
    } else if (typeof v === 'number') {
      if (finite && !Number.isFinite(v)) throw new RangeError(`${at(this, key)} must be finite, got ${v}`);
    } else if (v !== null && typeof v === 'object') {
      if (ArrayBuffer.isView(v)) {
        throw new TypeError(`${at(this, key)} is a ${v.constructor?.name ?? 'typed array'}: give a plain array`);
      }
      parents.set(v, [this, key]);
    }
    return replacer === undefined ? v : replacer(key, v);
  };
  try {
    return JSON.stringify(value, check);
  } catch (error) {
    if ((error instanceof RangeError || error?.name === 'InternalError') && nestsDeeperThan(value, kMaxArgumentDepth)) {
      throw withCause(new SpringBonesError('invalid-argument',
        `${what} nests too deeply to serialize as JSON (more than ${kMaxArgumentDepth} levels)`), error);
    }
    throw error;
  }
}

// The path of holder[key] from the argument (`.key`, `["odd key"]`, `[index]`), as JavaScript
// would write it; '' for the argument itself (JSON.stringify's wrapper holds it under '').
function pathTo(parents, holder, key) {
  const steps = [];
  for (let h = holder, k = key; parents.has(h) || k !== ''; ) {
    if (Array.isArray(h)) steps.push(`[${k}]`);
    else steps.push(/^[A-Za-z_$][\w$]*$/.test(k) ? `.${k}` : `[${JSON.stringify(k)}]`);
    if (!parents.has(h)) break;
    [h, k] = parents.get(h);
  }
  return steps.reverse().join('');
}

// Far deeper than any springBones, entity or params (the core edits 64 levels), far shallower
// than where JSON.stringify runs out of stack.
const kMaxArgumentDepth = 1000;

// Whether objects and arrays nest more than `limit` levels deep, walked without recursion over
// own enumerable values (what JSON.stringify writes, toJSON aside). On the error path only: it
// reads the properties a second time, and gives false if that throws.
function nestsDeeperThan(value, limit) {
  try {
    const stack = [[value, 0]];
    while (stack.length > 0) {
      const [v, depth] = stack.pop();
      if (v === null || typeof v !== 'object') continue;
      if (depth >= limit) return true;
      for (const child of Object.values(v)) stack.push([child, depth + 1]);
    }
  } catch {
    // a getter or proxy that throws
  }
  return false;
}
