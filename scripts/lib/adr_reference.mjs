// An independent reference of the spring-bone rules, written from their statement in
// docs/semantics.md and conformance/README.md (which adds where each step of a frame falls), in
// doubles, for the conformance pack (scripts/generate/make_conformance.mjs): which models entry applies,
// discovery, roots, chains, parameters (defaults, clamps, non-finite values), centers, the VRM
// update, the fixed-step rule with its substep cap, driver interpolation, and jumps. It shares no
// code with springbones: the pack's expected rotations come from here, and springbones is checked
// against them (conformance/run.mjs). Only similarity drivers (rotation, translation, uniform
// scale) are handled, which is all the pack uses; anything else throws.
import { length, linearOnly, mmul, invert, qmul, qnormalize, rotationBetween, scale, sub, add, transformPoint, transformVector, trsMatrix } from './fixtures/vec.mjs';

const TOKEN = 'springbone';
const MIN_LENGTH = 1e-6;

// docs/semantics.md, "Parameters": [min, max, default].
const RANGES = { stiffness: [0, 4, 2], gravityPower: [0, 2, 0], drag: [0, 1, 0.5] };
const DEFAULT_GRAVITY_DIR = [0, -1, 0];

const isObject = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);
const isCandidate = (name) => name.toLowerCase().includes(TOKEN);  // ASCII: names in the pack are ASCII

/** A scalar parameter as the rules read it: default when missing, not a number or not finite;
 *  clamped to its range otherwise. */
function readScalar(entry, key) {
  const [min, max, fallback] = RANGES[key];
  const v = entry[key];
  if (typeof v !== 'number' || !Number.isFinite(v)) return fallback;
  return Math.min(max, Math.max(min, v));
}

/** gravityDir: 3 finite numbers, normalized; anything else or a zero vector is [0, -1, 0]. */
function readGravityDir(entry) {
  const v = entry.gravityDir;
  if (!Array.isArray(v) || v.length !== 3 || !v.every((c) => typeof c === 'number' && Number.isFinite(c))) {
    return DEFAULT_GRAVITY_DIR;
  }
  const largest = Math.max(...v.map(Math.abs));
  if (!(largest > 1e-9)) return DEFAULT_GRAVITY_DIR;
  const u = v.map((c) => c / largest);
  return scale(u, 1 / length(u));
}

export function paramsOf(entry) {
  return {
    stiffness: readScalar(entry, 'stiffness'),
    gravityPower: readScalar(entry, 'gravityPower'),
    gravityDir: readGravityDir(entry),
    drag: readScalar(entry, 'drag'),
  };
}

/** The bone entries that apply ("Which models entry"), or null when none do. */
export function modelEntry(springBones, key) {
  if (springBones === null || springBones === undefined) return null;
  if (!isObject(springBones)) throw new Error('springBones must be an object');
  if (springBones.version !== 1) return null;
  if (!isObject(springBones.models)) return null;
  const entry = springBones.models[key];
  return isObject(entry) ? entry : null;
}

/** The models key from load options: contentHash, else the entity's main file for the body
 *  shape, else the GLB's own hash (given by the caller, computed with @dcl/hashing). */
export function modelKey(load, glbHash) {
  if (load.contentHash !== undefined) return load.contentHash;
  if (load.entity !== undefined) {
    const entity = load.entity;
    const shape = load.bodyShape;
    const matches = (urn) => urn === shape || urn.split(':').pop() === shape;
    const representation = entity.metadata.data.representations.find((r) => r.bodyShapes.some(matches));
    if (!representation) throw new Error(`no representation for ${shape}`);
    const file = entity.content.find((c) => c.file === representation.mainFile);
    if (!file) throw new Error(`main file ${representation.mainFile} not in content`);
    return file.hash;
  }
  return glbHash;
}

/**
 * The rig as the rules build it from glTF nodes (listed parents first, with name, children,
 * translation, rotation, scale) and the bone entries: joints in parents-first order, each with its
 * node, parent joint (or parent node for a root), tail offset, rest transform, parameters and
 * center node (-1 for world space).
 */
export function buildRig(nodes, bones) {
  const parent = new Array(nodes.length).fill(-1);
  nodes.forEach((n, i) => (n.children ?? []).forEach((c) => {
    if (c <= i) throw new Error('nodes must be listed parents first');
    parent[c] = i;
  }));
  const byName = new Map();
  nodes.forEach((n, i) => { if (!byName.has(n.name)) byName.set(n.name, i); });
  const candidate = nodes.map((n) => isCandidate(n.name));
  // Entries apply to candidates only, matched by exact name.
  const entryOf = nodes.map((n, i) => (candidate[i] && bones && isObject(bones[n.name]) && Object.hasOwn(bones, n.name)
    ? bones[n.name] : null));
  // Chains: a root is a candidate whose entry has isRoot === true; every descendant joins it; a
  // root inside a chain is a member.
  const chainOf = new Array(nodes.length).fill(-1);
  nodes.forEach((n, i) => {
    const inherited = parent[i] >= 0 ? chainOf[parent[i]] : -1;
    if (inherited >= 0) chainOf[i] = inherited;
    else if (entryOf[i] && entryOf[i].isRoot === true) chainOf[i] = i;
  });
  const centerNode = (entry) => {
    if (entry.center === null) return -1;
    if (typeof entry.center !== 'string') throw new Error('the pack only uses string or null centers');
    const c = byName.get(entry.center);
    if (c === undefined || candidate[c] || chainOf[c] >= 0) return -1;  // fallback: world space
    return c;
  };
  const joints = [];
  const jointOfNode = new Array(nodes.length).fill(-1);
  // Parents first, which is the node order here; the order of joints does not change the result,
  // as a joint reads only its parent's new pose.
  nodes.forEach((n, i) => {
    if (chainOf[i] < 0 || !(n.children?.length)) return;
    const pj = parent[i] >= 0 ? jointOfNode[parent[i]] : -1;
    const root = chainOf[i] === i;
    let params;
    let center;
    if (pj >= 0) { params = joints[pj].params; center = joints[pj].center; } else { center = -1; }
    const entry = entryOf[i];
    if (entry) {
      params = paramsOf(entry);
      if (Object.hasOwn(entry, 'center')) center = centerNode(entry);
    }
    if (!params) throw new Error(`no parameters for ${n.name}`);
    const tail = nodes[n.children[0]];
    jointOfNode[i] = joints.length;
    joints.push({
      name: n.name, node: i, parentJoint: pj, parentNode: root ? parent[i] : -1,
      tailLocal: tail.translation ?? [0, 0, 0],
      restT: n.translation ?? [0, 0, 0], restR: n.rotation ?? [0, 0, 0, 1], restS: n.scale ?? [1, 1, 1],
      params, center,
    });
  });
  const drivers = [...new Set(joints.flatMap((j) => [j.parentNode, j.center]).filter((d) => d >= 0))];
  return { joints, drivers, parent, byName };
}

// ---------------------------------------------------------------------------------------------
// Matrices (column-major arrays of 16) and quaternions ([x, y, z, w]).


/**
 * The unit quaternion of a rotation matrix given by its elements (mRC: row R, column C), by the
 * largest of the trace and the diagonal, so no branch divides by a small number.
 */
export function quaternionOfRotation(m00, m10, m20, m01, m11, m21, m02, m12, m22) {
  const trace = m00 + m11 + m22;
  let q;
  if (trace > 0) {
    const t = Math.sqrt(1 + trace) * 2;
    q = [(m21 - m12) / t, (m02 - m20) / t, (m10 - m01) / t, t / 4];
  } else if (m00 > m11 && m00 > m22) {
    const t = Math.sqrt(1 + m00 - m11 - m22) * 2;
    q = [t / 4, (m01 + m10) / t, (m02 + m20) / t, (m21 - m12) / t];
  } else if (m11 > m22) {
    const t = Math.sqrt(1 + m11 - m00 - m22) * 2;
    q = [(m01 + m10) / t, t / 4, (m12 + m21) / t, (m02 - m20) / t];
  } else {
    const t = Math.sqrt(1 + m22 - m00 - m11) * 2;
    q = [(m02 + m20) / t, (m12 + m21) / t, t / 4, (m10 - m01) / t];
  }
  return qnormalize(q);
}

/** A similarity matrix as translation, rotation and uniform scale. */
export function decompose(m) {
  const s = Math.hypot(m[0], m[1], m[2]);
  const sy = Math.hypot(m[4], m[5], m[6]);
  const sz = Math.hypot(m[8], m[9], m[10]);
  if (Math.abs(sy - s) > 1e-5 * s || Math.abs(sz - s) > 1e-5 * s) throw new Error('not a similarity');
  const r = [0, 1, 2, 4, 5, 6, 8, 9, 10].map((k) => m[k] / s);
  return { t: [m[12], m[13], m[14]], r: quaternionOfRotation(...r), s };
}

function nlerp(a, b, t) {
  const flip = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] < 0 ? -1 : 1;
  return qnormalize(a.map((c, i) => c + (flip * b[i] - c) * t));
}

const normalizeOr = (v, fallback) => {
  const l = length(v);
  return l > MIN_LENGTH && Number.isFinite(l) ? scale(v, 1 / l) : fallback;
};

// ---------------------------------------------------------------------------------------------
// Simulation

/**
 * One avatar's simulation state on a rig from buildRig. `frame(dt, driverWorld, jump)` advances
 * by a frame, given the world matrices of the rig's drivers (a Map node -> matrix) and whether
 * the caller asked for a jump; it returns each joint's local rotation.
 */
export class ReferenceInstance {
  constructor(rig, { stepHz = 60, maxSubsteps = 4, jumpDistance = 0.5, jumpAngle = 0.5 } = {}) {
    this.rig = rig;
    this.h = 1 / stepHz;
    this.maxSubsteps = maxSubsteps;
    this.jumpDistance = jumpDistance;
    this.jumpAngle = jumpAngle;
    this.accumulator = 0;
    this.seeded = false;
    this.current = rig.joints.map(() => null);   // tails in their center's space
    this.previous = rig.joints.map(() => null);
    this.rotations = rig.joints.map((j) => j.restR);
    this.jumps = 0;
  }

  // The driver matrix of one step: positions and scales lerped, rotations nlerped.
  static blend(a, b, t) {
    if (t >= 1) return b;
    const pa = decompose(a);
    const pb = decompose(b);
    const tr = pa.t.map((c, i) => c + (pb.t[i] - c) * t);
    const s = pa.s + (pb.s - pa.s) * t;
    return trsMatrix({ translation: tr, rotation: nlerp(pa.r, pb.r, t), scale: [s, s, s] });
  }

  // Walks every joint once, parents first, with the drivers of this step.
  run(drivers, h, seedOnly) {
    const world = [];
    this.rig.joints.forEach((joint, j) => {
      const parent = joint.parentJoint >= 0 ? world[joint.parentJoint]
        : joint.parentNode >= 0 ? drivers.get(joint.parentNode) : trsMatrix({});
      const restLocal = trsMatrix({ translation: joint.restT, rotation: joint.restR, scale: joint.restS });
      const restWorld = mmul(parent, restLocal);
      const head = [restWorld[12], restWorld[13], restWorld[14]];
      const restOffset = transformVector(restWorld, joint.tailLocal);
      const len = length(restOffset);
      const center = joint.center >= 0 ? drivers.get(joint.center) : null;
      const toCenter = (p) => (center ? transformPoint(invert(center), p) : p);
      const fromCenter = (p) => (center ? transformPoint(center, p) : p);
      if (seedOnly || !(len > MIN_LENGTH) || !(length(joint.tailLocal) > MIN_LENGTH)) {
        if (seedOnly) this.current[j] = this.previous[j] = toCenter(add(head, restOffset));
        world.push(restWorld);
        this.rotations[j] = joint.restR;
        return;
      }
      const p = joint.params;
      const restDir = scale(restOffset, 1 / len);
      const cur = this.current[j];
      const inertia = scale(sub(cur, this.previous[j]), 1 - p.drag);
      let next = fromCenter(add(cur, inertia));
      next = add(next, scale(restDir, p.stiffness * h), scale(p.gravityDir, p.gravityPower * h));
      const off = sub(next, head);
      const offLen = length(off);
      const offset = offLen > MIN_LENGTH && Number.isFinite(offLen) ? scale(off, len / offLen) : restOffset;
      const tail = add(head, offset);
      this.previous[j] = cur;
      this.current[j] = toCenter(tail);
      const axis = normalizeOr(joint.tailLocal, [0, 1, 0]);
      const localDir = normalizeOr(transformVector(invert(linearOnly(restWorld)), offset), axis);
      const rotation = qnormalize(qmul(joint.restR, rotationBetween(axis, localDir)));
      this.rotations[j] = rotation;
      world.push(mmul(parent, trsMatrix({ translation: joint.restT, rotation, scale: joint.restS })));
    });
  }

  // docs/semantics.md, "Jumps": a driver moving farther than jumpDistance, or turning more than
  // jumpAngle, per step of the frame.
  jumped(steps) {
    const per = Math.max(1, steps);
    for (const d of this.rig.drivers) {
      const a = decompose(this.prevPoses.get(d));
      const b = decompose(this.curPoses.get(d));
      if (this.jumpDistance > 0 && length(sub(b.t, a.t)) > this.jumpDistance * per) return true;
      const half = 0.5 * this.jumpAngle * per;
      const dq = Math.abs(a.r[0] * b.r[0] + a.r[1] * b.r[1] + a.r[2] * b.r[2] + a.r[3] * b.r[3]);
      if (this.jumpAngle > 0 && half < Math.PI / 2 && dq < Math.cos(half)) return true;
    }
    return false;
  }

  // Each driver's jump D = current x (last motion x previous)^-1, last motion = previous x older^-1;
  // every tail moves with the jump of its chain's driver (in world space), every driver's previous
  // pose with its own.
  carry() {
    const delta = new Map();
    for (const d of this.rig.drivers) {
      const from = this.prevPoses.get(d);
      const expected = mmul(mmul(from, invert(this.olderPoses.get(d))), from);
      delta.set(d, mmul(this.curPoses.get(d), invert(expected)));
    }
    const rootOf = (j) => { while (this.rig.joints[j].parentJoint >= 0) j = this.rig.joints[j].parentJoint; return j; };
    this.rig.joints.forEach((joint, j) => {
      const carrier = this.rig.joints[rootOf(j)].parentNode;
      const c = joint.center;
      const move = (stored) => {
        let w = c >= 0 ? transformPoint(this.prevPoses.get(c), stored) : stored;
        if (carrier >= 0) w = transformPoint(delta.get(carrier), w);
        return c >= 0 ? transformPoint(invert(mmul(delta.get(c), this.prevPoses.get(c))), w) : w;
      };
      this.current[j] = move(this.current[j]);
      this.previous[j] = move(this.previous[j]);
    });
    const carried = new Map();
    for (const d of this.rig.drivers) carried.set(d, mmul(delta.get(d), this.prevPoses.get(d)));
    this.prevPoses = carried;
    this.jumps += 1;
  }

  /** Advances by one frame; returns the joints' local rotations. */
  frame(dt, driverWorld, jumpRequested = false) {
    this.lastSteps = 0;
    if (!(dt > 0) || !Number.isFinite(dt)) return this.rotations;
    this.curPoses = new Map(this.rig.drivers.map((d) => [d, driverWorld.get(d)]));
    const wasSeeded = this.seeded;
    if (!this.seeded) {
      this.prevPoses = this.olderPoses = this.curPoses;
      this.run(this.curPoses, 0, true);
      this.seeded = true;
    }
    const h = this.h;
    const frameStart = this.accumulator;
    this.accumulator += dt;
    const crossed = Math.floor((this.accumulator + h * 1e-6) / h);
    const dropped = crossed > this.maxSubsteps;
    const steps = dropped ? this.maxSubsteps : crossed;
    if (wasSeeded && (jumpRequested || this.jumped(steps))) this.carry();
    for (let i = 0; i < steps; i++) {
      const at = dropped ? (i + 1) / steps : ((i + 1) * h - frameStart) / dt;
      const t = Math.min(1, Math.max(0, at));
      const drivers = new Map(this.rig.drivers.map((d) => [d, ReferenceInstance.blend(this.prevPoses.get(d), this.curPoses.get(d), t)]));
      this.run(drivers, h, false);
    }
    this.accumulator = dropped ? 0 : Math.max(0, this.accumulator - steps * h);
    this.olderPoses = this.prevPoses;
    this.prevPoses = this.curPoses;
    this.lastSteps = steps;
    return this.rotations;
  }
}

/**
 * World matrices of every node outside the spring chains for one frame: a node the pose names
 * takes that world matrix; any other takes its parent's world matrix times its rest local matrix.
 * Entries are rounded to float32, as a runtime's driver input is.
 */
export function poseWorld(nodes, parent, pose) {
  const world = [];
  nodes.forEach((n, i) => {
    if (Object.hasOwn(pose, n.name)) world.push(pose[n.name]);
    else {
      const local = trsMatrix(n);
      world.push(parent[i] >= 0 ? mmul(world[parent[i]], local) : local);
    }
  });
  return world.map((m) => m.map(Math.fround));
}
