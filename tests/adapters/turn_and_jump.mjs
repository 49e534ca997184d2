// The motion and the measure of the adapters' body-collider tests (tests/adapters/*_avatar_bones):
// the demo's hair worn on the demo's avatar, held by a node that stands 0.5 s, turns half a turn
// about the vertical in 0.3 s (up to 900 degrees per second), stands 0.7 s, jumps 0.4 m high
// (0.6 s in the air) and stands 1 s, as tests/wasm/avatar_bones.test.mjs drives the core by hand;
// and how deep the ponytail's tails get into the chest, shoulder and upper-arm shapes, measured in
// the simulation's own (glTF) space from the instance's world matrices and the shapes' carriers.

/** The eight shapes of the 'dcl-body' preset, by the bone that carries each, in the rig's order. */
export const kBodyShapes = ['Avatar_Head', 'Avatar_Neck', 'Avatar_Spine2', 'Avatar_Spine1', 'Avatar_LeftShoulder',
  'Avatar_RightShoulder', 'Avatar_LeftArm', 'Avatar_RightArm'];
/** The shapes the ponytail could swing into under the turn: chest, belly, shoulders, upper arms. */
export const kMeasuredShapes = kBodyShapes.slice(2);
export const kDt = 1 / 60;
export const kFrames = 186;
export const kHitRadius = 0.01;  // the demo's

/** The holder's pose at frame f: { yaw (radians about +Y), height (metres) }. */
export function holderPose(f) {
  const t = f * kDt;
  const turn = Math.min(1, Math.max(0, (t - 0.5) / 0.3));
  const air = t - 1.5;
  return { yaw: Math.PI * turn * turn * (3 - 2 * turn), height: air > 0 && air < 0.6 ? 0.4 * 4 * (air / 0.6) * (1 - air / 0.6) : 0 };
}

const transform = (m, o, [x, y, z]) => [
  m[o] * x + m[o + 4] * y + m[o + 8] * z + m[o + 12],
  m[o + 1] * x + m[o + 5] * y + m[o + 9] * z + m[o + 13],
  m[o + 2] * x + m[o + 6] * y + m[o + 10] * z + m[o + 14],
];
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const maxScale = (m) => Math.sqrt(Math.max(...[0, 4, 8].map((o) => m[o] * m[o] + m[o + 1] * m[o + 1] + m[o + 2] * m[o + 2])));

/** How far `p` is inside the capsule a-b of `radius` (negative outside). */
function depthInside(p, a, b, radius) {
  const ab = sub(b, a);
  const length2 = dot(ab, ab);
  const t = length2 > 0 ? Math.min(1, Math.max(0, dot(ab, sub(p, a)) / length2)) : 0;
  const closest = [a[0] + ab[0] * t, a[1] + ab[1] * t, a[2] + ab[2] * t];
  return radius - Math.sqrt(dot(sub(p, closest), sub(p, closest)));
}

/**
 * The deepest ponytail tail in each measured shape, over the frames measure() is called for.
 * `rig`: the worn rig (its joints); `shapes`: the preset's colliders measured on the avatar (from a
 * rig that has them, so a run without colliders is measured against the same shapes).
 */
export class DeepestTails {
  constructor(rig, shapes) {
    this.joints = rig.joints.filter((j) => /ponytail/i.test(rig.joints[j.chain].name)).map((j) => ({ index: rig.joints.indexOf(j), tail: j.tailOffset }));
    this.shapes = kMeasuredShapes.map((node) => shapes.find((c) => c.node === node));
    this.deepest = Object.fromEntries(kMeasuredShapes.map((node) => [node, -Infinity]));
  }

  /** One frame: `world` the instance's worldMatrices, `carrier(name)` the shape bone's world matrix (glTF space). */
  measure(world, carrier) {
    for (const c of this.shapes) {
      const m = carrier(c.node);
      const a = transform(m, 0, c.offset);
      const b = transform(m, 0, c.tail ?? c.offset);
      const radius = c.radius * maxScale(m);
      for (const { index, tail } of this.joints) {
        this.deepest[c.node] = Math.max(this.deepest[c.node], depthInside(transform(world, 16 * index, tail), a, b, radius));
      }
    }
  }

  /** Per shape and `all`, metres inside (negative: outside). */
  get result() {
    return { ...this.deepest, all: Math.max(...Object.values(this.deepest)) };
  }
}

export const mm = (v) => `${(v * 1000).toFixed(1)} mm`;
export const describeDepths = (d) => kMeasuredShapes.map((n) => `${n.slice(7)} ${mm(d[n])}`).join(', ');
