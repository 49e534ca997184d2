// Arguments that cross into WebAssembly as JSON text, as the creator tools take them: an object the
// caller gives (serialized here, with what JSON.stringify would silently change refused first) or
// the caller's own JSON text. The runtime's inputs cross as typed input instead (typed_value.js), so
// only creator_tools.js imports this file: what the runtime's bundle and the two modules loaded on
// demand share is one chunk of helpers (scripts/lib/minify.mjs), and a helper only some of them import
// would make a second.

import { checkWellFormed, isWellFormed } from './arguments.js';
import { SpringBonesError, withCause } from './errors.js';

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
