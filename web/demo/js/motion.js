// The preview's scripted motions besides the avatar's clips: the spin and the shake, as numbers
// and one function with no DOM and no three.js, so Node tests drive the same motions as the page.

export const kSpinSpeed = 120;       // degrees per second with "spin"
export const kShakeSeconds = 1.4;

/**
 * The shake at t seconds since it started: a decaying side-to-side jolt of the avatar's holder
 * (x, y in metres, roll in radians), written into `out` (the frame loop allocates nothing); zero
 * outside [0, kShakeSeconds].
 */
export function shakeOffset(t, out) {
  if (t < 0 || t > kShakeSeconds) {
    out.x = 0; out.y = 0; out.roll = 0;
    return out;
  }
  const envelope = Math.exp(-3 * t);
  out.x = 0.14 * envelope * Math.sin(2 * Math.PI * 3.5 * t);
  out.y = 0.04 * envelope * Math.sin(2 * Math.PI * 7 * t);
  out.roll = 0.08 * envelope * Math.sin(2 * Math.PI * 3.5 * t + 0.6);
  return out;
}
