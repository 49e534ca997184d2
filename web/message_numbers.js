// The numbers in the runtime module's messages, written here. The module carries no number
// formatting: a message's C++ (its one home) leaves each number as a placeholder, and this file
// writes it with the digits C++'s snprintf writes natively (src/common/message_number.h has the
// placeholders; tests/wasm/message_numbers.test.mjs holds the two sides together). printf rounds
// the exact binary value, ties to even, so the digits come from exact integer arithmetic, not from
// toPrecision, which rounds ties away from zero.

const kMark = 0xff;
const kCut = 0x63;  // 'c'
const kCutEnd = 0x65;  // 'e'
const utf8 = new TextDecoder();
const encoder = new TextEncoder();
const bits = new DataView(new ArrayBuffer(8));

/** round(|x| * 10^scale), ties to even, exactly (x finite). */
function scaledInteger(x, scale) {
  bits.setFloat64(0, Math.abs(x));
  const word = bits.getBigUint64(0);
  const biased = Number(word >> 52n);
  let mantissa = word & 0xfffffffffffffn;
  if (biased !== 0) mantissa |= 1n << 52n;
  const exponent = (biased === 0 ? 1 : biased) - 1075;
  let num = mantissa;
  let den = 1n;
  if (exponent >= 0) num <<= BigInt(exponent);
  else den <<= BigInt(-exponent);
  if (scale >= 0) num *= 10n ** BigInt(scale);
  else den *= 10n ** BigInt(-scale);
  const q = num / den;
  const twice = (num % den) * 2n;
  return twice > den || (twice === den && (q & 1n) === 1n) ? q + 1n : q;
}

/**
 * The first `precision` significant digits of |x| (finite, not 0) as printf's %e and %g round
 * them: [digits as a BigInt of exactly `precision` digits, the decimal exponent of the first].
 */
export function significantDigits(x, precision) {
  let exponent = Math.floor(Math.log10(Math.abs(x)));  // exact or one off; corrected below
  for (;;) {
    const digits = scaledInteger(x, precision - 1 - exponent);
    if (digits >= 10n ** BigInt(precision)) exponent += 1;
    else if (digits < 10n ** BigInt(precision - 1)) exponent -= 1;
    else return [digits, exponent];
  }
}

/** printf's %.{precision}g of a finite x (its sign apart). */
function formatG(x, precision) {
  if (x === 0) return '0';
  const [digits, exponent] = significantDigits(x, precision);
  const text = digits.toString();
  if (exponent < -4 || exponent >= precision) {
    const fraction = text.slice(1).replace(/0+$/, '');
    const power = String(Math.abs(exponent)).padStart(2, '0');
    return `${text[0]}${fraction ? `.${fraction}` : ''}e${exponent < 0 ? '-' : '+'}${power}`;
  }
  const whole = exponent >= 0 ? text.slice(0, exponent + 1) : '0';
  const fraction = (exponent >= 0 ? text.slice(exponent + 1) : '0'.repeat(-exponent - 1) + text).replace(/0+$/, '');
  return fraction ? `${whole}.${fraction}` : whole;
}

/** printf's %f of a finite x (its sign apart). */
function formatF(x) {
  const text = scaledInteger(x, 6).toString().padStart(7, '0');
  return `${text.slice(0, -6)}.${text.slice(-6)}`;
}

/**
 * A number as a placeholder asks for it: `conversion` 'g' (%.{precision}g), 'f' (%f) or 't' (%f
 * without trailing zeros, nor a point left at the end); `negative` is the sign bit (printf writes
 * "-nan" and "-0").
 */
export function formatNumber(x, conversion, precision, negative = x < 0 || Object.is(x, -0)) {
  let text;
  if (Number.isNaN(x)) text = 'nan';
  else if (!Number.isFinite(x)) text = 'inf';
  else if (conversion === 'g') text = formatG(x, Math.max(precision, 1));
  else text = formatF(x);
  if (conversion === 't' && Number.isFinite(x)) text = text.replace(/0+$/, '').replace(/\.$/, '');
  return negative ? `-${text}` : text;
}

/** The bytes of a UTF-8 character cut at the end of `bytes` (0 when the last one is whole). */
function cutCharacterBytes(bytes) {
  let trailing = 0;
  while (trailing < bytes.length && trailing < 3 && (bytes[bytes.length - 1 - trailing] & 0xc0) === 0x80) ++trailing;
  if (trailing === bytes.length) return trailing;
  const lead = bytes[bytes.length - 1 - trailing];
  const length = lead < 0x80 ? 1 : lead >= 0xf0 ? 4 : lead >= 0xe0 ? 3 : lead >= 0xc0 ? 2 : 1;
  return length > trailing + 1 ? trailing + 1 : 0;
}

const twoDigits = (bytes, at) => (bytes[at] - 48) * 10 + (bytes[at + 1] - 48);

/** Writes bytes[start, end) with its placeholders into `out` (an array of bytes). */
function writeInto(out, bytes, start, end) {
  for (let i = start; i < end;) {
    if (bytes[i] !== kMark) {
      out.push(bytes[i++]);
    } else if (bytes[i + 1] === kCut) {
      // appendCut: the text whole when it fits, else its first max - 3 bytes, each byte of a cut
      // character as U+FFFD, and "...".
      const max = twoDigits(bytes, i + 2);
      let close = i + 4;
      while (!(bytes[close] === kMark && bytes[close + 1] === kCutEnd)) ++close;
      const text = [];
      writeInto(text, bytes, i + 4, close);
      if (text.length <= max) {
        out.push(...text);
      } else {
        const kept = text.slice(0, max - 3);
        const cut = cutCharacterBytes(kept);
        out.push(...kept.slice(0, kept.length - cut));
        for (let k = 0; k < cut; ++k) out.push(0xef, 0xbf, 0xbd);
        out.push(0x2e, 0x2e, 0x2e);
      }
      i = close + 2;
    } else {
      const conversion = String.fromCharCode(bytes[i + 1]);
      const word = BigInt(`0x${String.fromCharCode(...bytes.subarray(i + 4, i + 20))}`);
      bits.setBigUint64(0, word);
      out.push(...encoder.encode(formatNumber(bits.getFloat64(0), conversion, twoDigits(bytes, i + 2), word >> 63n === 1n)));
      i += 20;
    }
  }
}

/** A string of the runtime (UTF-8 bytes) with the numbers of its placeholders written. */
export function messageText(bytes) {
  if (!bytes.includes(kMark)) return utf8.decode(bytes);
  const out = [];
  writeInto(out, bytes, 0, bytes.length);
  return utf8.decode(new Uint8Array(out));
}
