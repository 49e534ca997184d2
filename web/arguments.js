// The checks of one argument value, whatever call it comes to: its type (a TypeError) and its
// range (a RangeError), before anything crosses into WebAssembly. Where the checks of the API live:
//   - here, a value on its own: a number in a range, a vector, a string, bytes, an options
//     object's keys, the wind;
//   - json_arguments.js, a value the creator tools take as JSON text (an object or the caller's text);
//   - rig_options.js, the option objects of loadRig and createInstance, key by key, written with
//     the checks of this file (the one home of the rules over those options);
//   - models_entry.js, springBones and which of its models entries applies.
// A class checks nothing itself but its own state (disposed, a joint index within its rig).

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

export const isWellFormed = typeof String.prototype.isWellFormed === 'function'
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
 * TypeError, as an undefined element is, rather than skipped by map() or written as null.
 */
export function checkDenseArray(what, array) {
  for (let i = 0; i < array.length; ++i) {
    if (!(i in array)) throw new TypeError(`${what}[${i}] is a hole (a sparse array); give every element`);
    if (array[i] === undefined) throw new TypeError(`${what}[${i}] is undefined`);
  }
  return array;
}

export function toBytes(what, value) {
  if (value instanceof Uint8Array) return value;
  if (value instanceof ArrayBuffer) return new Uint8Array(value);
  throw new TypeError(`${what} must be a Uint8Array or an ArrayBuffer`);
}

export function checkRange(what, value, min, max) {
  if (typeof value !== 'number') throw new TypeError(`${what} must be a number`);
  if (!(value >= min && value <= max)) throw new RangeError(`${what} must be in [${min}, ${max}], got ${value}`);
  return value;
}

export function checkFinite(what, value) {
  if (typeof value !== 'number') throw new TypeError(`${what} must be a number`);
  if (!Number.isFinite(value)) throw new RangeError(`${what} must be finite, got ${value}`);
  return value;
}

// A finite number that is finite as float32 too (|value| below 2^128 less half a float32 step).
export function checkFloat32(what, value) {
  checkFinite(what, value);
  if (!Number.isFinite(Math.fround(value))) throw new RangeError(`${what} must be within float32's range (about ±3.4e38), got ${value}`);
  return value;
}

export function checkOneOf(what, value, choices) {
  if (typeof value !== 'string') throw new TypeError(`${what} must be a string`);
  if (!choices.includes(value)) throw new RangeError(`${what} must be one of ${choices.join(', ')}, got '${value}'`);
  return value;
}

export function checkVec3(what, value) {
  if (!(Array.isArray(value) || ArrayBuffer.isView(value)) || value.length !== 3) {
    throw new TypeError(`${what} must be an array of 3 numbers`);
  }
  if (Array.isArray(value)) checkDenseArray(what, value);  // a hole is a TypeError that says so
  const out = Array.from(value);
  for (const v of out) {
    if (typeof v !== 'number') throw new TypeError(`${what} must be an array of 3 numbers`);
    checkFinite(what, v);
  }
  return out;
}

// A direction (3 finite numbers, not all 0) as it crosses, as float32: one whose largest
// component is beyond float32's normal range ([1e39, 0, 0] would be infinite there, [1e-46, 0, 0]
// zero) is divided by that component's size first, in double precision. The core makes it unit,
// scaled alike first, so [1e20, 0, 0] or [1e-25, 0, 0] do not overflow or underflow there either.
// Others cross unchanged, so that native and JavaScript callers giving the same direction get
// the same bits.
export function scaledDirection(v) {
  const largest = Math.max(Math.abs(v[0]), Math.abs(v[1]), Math.abs(v[2]));
  return largest >= 2 ** -126 && largest < 2 ** 127 ? v : v.map((c) => c / largest);
}

export function checkNonNegative(what, value) {
  if (typeof value !== 'number') throw new TypeError(`${what} must be a number`);
  if (!(Number.isFinite(value) && value >= 0)) throw new RangeError(`${what} must be finite and >= 0, got ${value}`);
  return value;
}

export function checkInteger(what, value, min, max) {
  if (typeof value !== 'number') throw new TypeError(`${what} must be a number`);
  if (!Number.isInteger(value) || value < min || value > max) {
    throw new RangeError(`${what} must be an integer in [${min}, ${max}], got ${value}`);
  }
  return value;
}

export function checkDt(dt) {
  if (typeof dt !== 'number') throw new TypeError('step: dt must be a number of seconds');
  return checkFinite('step: dt', dt);
}

const kWindKeys = ['direction', 'strength', 'gustFrequency', 'seed'];

// setWind's argument, checked against the core's limits: [dx, dy, dz, strength, gustFrequency,
// seed]; null is no wind.
export function windArguments(where, wind, limits) {
  if (wind === null) return [1, 0, 0, 0, 0, 0];
  if (typeof wind !== 'object' || Array.isArray(wind)) {
    throw new TypeError(`${where}: wind must be an object {direction, strength, gustFrequency?, seed?} or null`);
  }
  checkKeys(`${where}: wind`, wind, kWindKeys);
  const direction = checkVec3(`${where}: wind.direction`, wind.direction);
  const strength = checkRange(`${where}: wind.strength`, wind.strength, 0, limits.maxWindStrength);
  const gustFrequency = wind.gustFrequency === undefined
    ? 0 : checkRange(`${where}: wind.gustFrequency`, wind.gustFrequency, 0, limits.maxGustFrequency);
  const seed = wind.seed === undefined ? 0 : checkInteger(`${where}: wind.seed`, wind.seed, 0, 0xffffffff);
  if (direction.every((v) => v === 0)) {
    if (strength > 0) throw new RangeError(`${where}: wind.direction must not be zero`);
    return [1, 0, 0, strength, gustFrequency, seed];
  }
  return [...scaledDirection(direction), strength, gustFrequency, seed];
}
