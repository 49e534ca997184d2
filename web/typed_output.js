// What the WebAssembly modules hand back as typed values (springbones/boundary.h: the rig
// description, failures, limits, stats), read into plain values: the encoding of typed input
// (web/typed_value.js writes it; the tags are typed_encoding.js's), plus the tag float that only
// the runtime writes. No JSON text crosses, and the modules write no number in decimal: the numbers
// come out as the JSON text the modules wrote before gave them (exactly the same JavaScript
// numbers), and strings with their message numbers written (message_numbers.js).
//
// Numbers, as C++ wrote them in that text:
//  - integers with fewer than 16 digits exactly (-0 as 0);
//  - a float (the tag float): the shortest of its %.1g ... %.9g texts that reads back as the same
//    float, where "reads back" was C++'s own parse, exact only for a decimal exponent within
//    +-22 (beyond it, 9 digits);
//  - a double (the tag number): its %.15g text;
//  - non-finite numbers as they are (the modules write null where JSON had one).
import { messageText, significantDigits } from './message_numbers.js';
import { kTypedTags as kTag } from './typed_encoding.js';

const utf8 = new TextDecoder();

/** A float's value as its shortest %g text that C++ reads back as the same float. */
export function floatNumber(f) {
  if (!Number.isFinite(f)) return f;
  if (Number.isInteger(f) && Math.abs(f) < 1e15) return f + 0;
  let value;
  for (let precision = 1; precision <= 9; ++precision) {
    const [digits, exponent] = significantDigits(f, precision);
    value = Number(`${f < 0 ? '-' : ''}${digits}e${exponent - precision + 1}`);
    // The exponent C++'s reader saw: %g's fixed notation keeps it within range; the scientific
    // one has the digits without trailing zeros.
    const kept = digits.toString().replace(/0+$/, '').length;
    const fixed = exponent >= -4 && exponent < precision;
    if ((fixed || Math.abs(exponent - kept + 1) <= 22) && Math.fround(value) === f) break;
  }
  return value;
}

/** A double's value as its %.15g text. */
export function doubleNumber(x) {
  if (!Number.isFinite(x)) return x;
  if (Number.isInteger(x) && Math.abs(x) < 1e15) return x + 0;
  const [digits, exponent] = significantDigits(x, 15);
  return Number(`${x < 0 ? '-' : ''}${digits}e${exponent - 14}`);
}

/** One typed value in `bytes` as a plain value (objects' members in the order written). */
export function decodeTyped(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let at = 0;
  const u32 = () => {
    at += 4;
    return view.getUint32(at - 4, true);
  };
  const text = (decode) => {
    const length = u32();
    at += length;
    return decode(bytes.subarray(at - length, at));
  };
  // Iterative: [container, members left, key of the next member].
  const open = [];
  let root;
  do {
    const top = open[open.length - 1];
    const key = top && !Array.isArray(top[0]) ? text((b) => utf8.decode(b)) : undefined;
    const tag = bytes[at++];
    let value;
    if (tag === kTag.null) value = null;
    else if (tag === kTag.false) value = false;
    else if (tag === kTag.true) value = true;
    else if (tag === kTag.number) {
      value = doubleNumber(view.getFloat64(at, true));
      at += 8;
    } else if (tag === kTag.float) {
      value = floatNumber(view.getFloat32(at, true));
      at += 4;
    } else if (tag === kTag.string) value = text(messageText);
    else if (tag === kTag.array || tag === kTag.object) value = tag === kTag.array ? [] : {};
    else throw new Error(`typed output: unknown tag ${tag} at byte ${at - 1}`);
    if (top === undefined) root = value;
    else if (key === undefined) top[0].push(value);
    else top[0][key] = value;
    if (top !== undefined) top[1] -= 1;
    if (typeof value === 'object' && value !== null) open.push([value, u32()]);
    while (open.length > 0 && open[open.length - 1][1] === 0) open.pop();
  } while (open.length > 0);
  if (at !== bytes.length) throw new Error(`typed output: ${bytes.length - at} bytes after the value`);
  return root;
}

/** A copy of the typed result a module's call left (`length` bytes, wasm/binding_errors.h). */
export function typedResult(m, length) {
  const at = m.typedResult();
  return m.HEAPU8.slice(at, at + length);
}

/** The typed result a module's call left, read. */
export function takeTyped(m, length) {
  const at = m.typedResult();
  return decodeTyped(m.HEAPU8.subarray(at, at + length));
}
