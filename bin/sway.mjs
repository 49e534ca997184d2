// The scripted driver motion of `springbones simulate --drive sway` (bin/springbones-cli.mjs) and
// of the native/WebAssembly parity test. tools/dump_rotations.cpp computes the very same numbers:
// keep the two in step.
//
// The whole avatar sways: every driver's world matrix is S(t) x rest, where S(t) turns the avatar
// a little about Y and Z and moves it a few centimetres, each part following a sine of its own
// frequency. The sine is Bhaskara I's rational approximation (error below 0.002) rather than
// Math.sin, and everything is +, -, *, / and sqrt on doubles in a fixed order, because those are
// correctly rounded in both languages while sin is not: the driver matrices then agree bit for bit
// between JavaScript and C++, and any difference in the rotations comes from the two builds.

const kPi = 3.141592653589793;

/** sin(x), Bhaskara I's approximation on each half period. */
export function sine(x) {
  const twoPi = 2 * kPi;
  let r = x - twoPi * Math.floor(x / twoPi);
  let sign = 1;
  if (r >= kPi) {
    r = r - kPi;
    sign = -1;
  }
  const p = r * (kPi - r);
  return (sign * (16 * p)) / (5 * kPi * kPi - 4 * p);
}

/** S(t): column-major 4x4 (doubles) of the avatar's sway at time t seconds. */
export function swayTransform(t, out = new Float64Array(16)) {
  const u = 0.2 * sine(2 * kPi * 0.7 * t);        // about Y
  const v = 0.15 * sine(2 * kPi * 1.3 * t + 1);   // about Z
  const n = Math.sqrt(1 + u * u + v * v);
  const x = 0;
  const y = u / n;
  const z = v / n;
  const w = 1 / n;
  out[0] = 1 - 2 * (y * y + z * z);
  out[1] = 2 * (x * y + z * w);
  out[2] = 2 * (x * z - y * w);
  out[3] = 0;
  out[4] = 2 * (x * y - z * w);
  out[5] = 1 - 2 * (x * x + z * z);
  out[6] = 2 * (y * z + x * w);
  out[7] = 0;
  out[8] = 2 * (x * z + y * w);
  out[9] = 2 * (y * z - x * w);
  out[10] = 1 - 2 * (x * x + y * y);
  out[11] = 0;
  out[12] = 0.08 * sine(2 * kPi * 0.9 * t);
  out[13] = 0.02 * sine(2 * kPi * 2.1 * t);
  out[14] = 0.05 * sine(2 * kPi * 0.5 * t + 2);
  out[15] = 1;
  return out;
}

/**
 * Writes S(t) x rest[d] into out[d] for every driver (16 floats each). `rest` and `out` are
 * Float32Arrays of the same length; `scratch` a Float64Array(16) to allocate nothing per frame.
 */
export function swayDrivers(rest, out, t, scratch = new Float64Array(16)) {
  const s = swayTransform(t, scratch);
  for (let base = 0; base < rest.length; base += 16) {
    for (let c = 0; c < 4; ++c) {
      const m0 = rest[base + 4 * c];
      const m1 = rest[base + 4 * c + 1];
      const m2 = rest[base + 4 * c + 2];
      const m3 = rest[base + 4 * c + 3];
      for (let r = 0; r < 4; ++r) {
        out[base + 4 * c + r] = s[r] * m0 + s[4 + r] * m1 + s[8 + r] * m2 + s[12 + r] * m3;
      }
    }
  }
}
