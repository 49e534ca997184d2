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
  return value;
}

export function toBytes(what, value) {
  if (value instanceof Uint8Array) return value;
  if (value instanceof ArrayBuffer) return new Uint8Array(value);
  throw new TypeError(`${what} must be a Uint8Array or an ArrayBuffer`);
}

// Objects are serialised; strings are taken as JSON text (the core parses and reports errors);
// null/undefined is "no spring bones" where allowed.
export function toJsonText(what, value, allowNull) {
  if (typeof value === 'string') return value;
  if (value === null || value === undefined) {
    if (allowNull) return 'null';
    throw new TypeError(`${what} must be an object or JSON text`);
  }
  if (typeof value !== 'object') {
    throw new TypeError(`${what} must be an object, JSON text${allowNull ? ', null or undefined' : ''}`);
  }
  return stringifyArgument(what, value);
}

// JSON.stringify of a caller's value. One nested too deeply for the engine's stack (thousands of
// levels: V8 and JavaScriptCore throw a RangeError, Firefox an InternalError) is an invalid
// argument, reported as the core reports params nested deeper than it edits, rather than an
// engine error escaping the API. Cycles and BigInt still throw JSON.stringify's TypeError, and
// an error thrown by a toJSON or a getter goes through as it is.
export function stringifyArgument(what, value, replacer) {
  try {
    return JSON.stringify(value, replacer);
  } catch (error) {
    if ((error instanceof RangeError || error?.name === 'InternalError') && nestsDeeperThan(value, kMaxArgumentDepth)) {
      throw withCause(new SpringBonesError('invalid-argument',
        `${what} nests too deeply to serialize as JSON (more than ${kMaxArgumentDepth} levels)`), error);
    }
    throw error;
  }
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
