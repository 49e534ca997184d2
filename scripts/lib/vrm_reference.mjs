// An independent reference of VRMC_springBone 1.0 as docs/semantics.md states it ("VRM avatars",
// "Colliders", "Angle limits"), in doubles, for the VRM part of the conformance pack
// (scripts/generate/make_conformance_vrm.mjs): joints aiming at the next joint of their spring, per-joint
// parameters with the VRM defaults and ranges, a spring's center, collider groups (a collider in two
// of a spring's groups pushes twice), sphere and capsule colliders, VRMC_springBone_extended_collider
// (plane, inside sphere, inside capsule), VRMC_springBone_limit with UniVRM's import rules, and the
// fixed-step rule of conformance/README.md. It shares no code with springbones. Only what the pack
// uses is handled (a next joint that is a direct child, similarity drivers); anything else throws, so a case cannot silently leave the reference's ground.
import { ReferenceInstance, quaternionOfRotation } from './adr_reference.mjs';
import { add, cross, dot, invert, length, linearOnly, mmul, qmul, qnormalize, rotationBetween, scale, sub, transformPoint, transformVector, trsMatrix } from './fixtures/vec.mjs';

const MIN_LENGTH = 1e-6;
// A limit-space direction is singular when the squared length of the components that would give it
// an azimuth is under the square root of double's epsilon (docs/semantics.md, "Angle limits").
const SINGULAR = Math.sqrt(Number.EPSILON);
const LIMIT_VERSIONS = new Set(['1.0', '1.0-draft']);
const EXTENDED_VERSIONS = new Set(['1.0', '1.0-draft']);

const isNumber = (v) => typeof v === 'number' && Number.isFinite(v);
const vec3 = (v, fallback) => (Array.isArray(v) && v.length === 3 && v.every(isNumber) ? v : fallback);
const nonNegative = (v, fallback) => (isNumber(v) ? Math.max(0, v) : fallback);

/** A joint's parameters: VRM 1.0 defaults; gravityDir's length folded into gravityPower. */
function paramsOf(joint) {
  const gravityDir = vec3(joint.gravityDir, [0, -1, 0]);
  const dirLength = length(gravityDir);
  return {
    stiffness: nonNegative(joint.stiffness, 1),
    gravityPower: nonNegative(joint.gravityPower, 0) * dirLength,
    gravityDir: dirLength > 0 ? scale(gravityDir, 1 / dirLength) : [0, -1, 0],
    drag: isNumber(joint.dragForce) ? Math.min(1, Math.max(0, joint.dragForce)) : 0.5,
    hitRadius: Math.min(1e6, nonNegative(joint.hitRadius, 0)),
  };
}

/** A collider's shape: the extension's when it can be read, else the base shape. */
function shapeOf(collider) {
  const extended = collider.extensions?.VRMC_springBone_extended_collider;
  if (extended && EXTENDED_VERSIONS.has(extended.specVersion) && extended.shape) {
    const { sphere, capsule, plane } = extended.shape;
    if (plane) return { kind: 'plane', offset: vec3(plane.offset, [0, 0, 0]), normal: vec3(plane.normal, [0, 0, 1]) };
    if (sphere) return { kind: 'sphere', inside: sphere.inside === true, offset: vec3(sphere.offset, [0, 0, 0]), radius: sphere.radius ?? 0 };
    if (capsule) {
      return {
        kind: 'capsule', inside: capsule.inside === true, offset: vec3(capsule.offset, [0, 0, 0]),
        tail: vec3(capsule.tail, [0, 0, 0]), radius: capsule.radius ?? 0,
      };
    }
  }
  const { sphere, capsule } = collider.shape;
  if (sphere) return { kind: 'sphere', inside: false, offset: vec3(sphere.offset, [0, 0, 0]), radius: sphere.radius ?? 0 };
  return { kind: 'capsule', inside: false, offset: vec3(capsule.offset, [0, 0, 0]), tail: vec3(capsule.tail, [0, 0, 0]), radius: capsule.radius ?? 0 };
}

/** UniVRM's import rules for a joint's VRMC_springBone_limit: the limit, or null. */
export function limitOf(joint) {
  const extension = joint.extensions?.VRMC_springBone_limit;
  if (!extension || !LIMIT_VERSIONS.has(extension.specVersion)) return null;
  const limit = extension.limit;
  if (limit === null || typeof limit !== 'object') return null;
  const kinds = ['cone', 'hinge', 'spherical'].filter((k) => Object.hasOwn(limit, k));
  if (kinds.length !== 1) return null;  // none, or two: ignored
  const kind = kinds[0];
  const shape = limit[kind];
  const clamp = (v, max) => (isNumber(v) ? Math.min(max, Math.max(0, v)) : max);
  let rotation = [0, 0, 0, 1];
  if (shape.rotation !== undefined) {
    const q = shape.rotation;
    const largest = Math.max(...q.map(Math.abs));
    const scaled = q.map((c) => c / largest);
    rotation = qnormalize(scaled);
  }
  if (kind === 'spherical') return { kind, pitch: clamp(shape.pitch, Math.PI), yaw: clamp(shape.yaw, Math.PI / 2), rotation };
  return { kind, angle: clamp(shape.angle, Math.PI), rotation };
}

/**
 * The rig of a glTF document with VRMC_springBone: joints in spring order (each a node aiming at
 * the next joint, its direct child), each with parameters, a center node (-1: world), its collider
 * indices in test order and its limit; colliders with node and shape; drivers (the nodes whose
 * world matrices the caller supplies).
 */
export function buildVrmRig(gltf) {
  const nodes = gltf.nodes;
  const parent = new Array(nodes.length).fill(-1);
  nodes.forEach((n, i) => (n.children ?? []).forEach((c) => { parent[c] = i; }));
  const ext = gltf.extensions.VRMC_springBone;
  const colliders = (ext.colliders ?? []).map((c) => ({ node: c.node, shape: shapeOf(c) }));
  const groups = ext.colliderGroups ?? [];
  const joints = [];
  const jointOfNode = new Map();
  for (const spring of ext.springs) {
    // Groups listed twice by a spring, and colliders twice by a group, count once; a collider in two
    // groups is tested once per group.
    const colliderList = [...new Set(spring.colliderGroups ?? [])].flatMap((g) => [...new Set(groups[g].colliders)]);
    const center = spring.center ?? -1;
    spring.joints.slice(0, -1).forEach((joint, k) => {
      const next = spring.joints[k + 1].node;
      const node = nodes[joint.node];
      if (parent[next] !== joint.node) throw new Error('the reference handles next joints that are direct children only');
      const pj = jointOfNode.get(parent[joint.node]) ?? -1;
      jointOfNode.set(joint.node, joints.length);
      joints.push({
        node: joint.node, name: node.name, parentJoint: pj, parentNode: pj >= 0 ? -1 : parent[joint.node],
        restT: node.translation ?? [0, 0, 0], restR: node.rotation ?? [0, 0, 0, 1], restS: node.scale ?? [1, 1, 1],
        tailLocal: nodes[next].translation ?? [0, 0, 0],
        params: paramsOf(joint), center, colliders: colliderList, limit: limitOf(joint),
      });
    });
  }
  const drivers = [...new Set([
    ...joints.filter((j) => j.parentJoint < 0).map((j) => j.parentNode),
    ...joints.map((j) => j.center), ...colliders.map((c) => c.node),
  ].filter((d) => d >= 0))];
  for (const d of drivers) if (jointOfNode.has(d)) throw new Error('a driver that is a joint is not used by the pack');
  return { joints, colliders, drivers, parent };
}

// ---------------------------------------------------------------------------------------------

const qrotate = (q, v) => {
  const u = [q[0], q[1], q[2]];
  const t = scale(cross(u, v), 2);
  return add(v, scale(t, q[3]), cross(u, t));
};
const qinverse = (q) => [-q[0], -q[1], -q[2], q[3]];

/** The rotation of a matrix with its (uniform or not) axis scales divided out. */
function rotationOf(m) {
  const columns = [0, 4, 8].map((k) => { const s = Math.hypot(m[k], m[k + 1], m[k + 2]); return [m[k] / s, m[k + 1] / s, m[k + 2] / s]; });
  return quaternionOfRotation(...columns.flat());
}

/** Keeps a unit limit-space direction within the limit (docs/semantics.md's table). */
export function limitDirection(limit, d) {
  const [x, y, z] = d;
  if (limit.kind === 'cone') {
    const cos = Math.cos(limit.angle);
    if (!(y < cos)) return d;
    const sin = Math.sin(limit.angle);
    const horizontal = x * x + z * z;
    if (horizontal < SINGULAR) return [0, cos, sin];  // -Y: the boundary on the +Z side
    const k = sin / Math.sqrt(horizontal);
    return [x * k, cos, z * k];
  }
  if (limit.kind === 'hinge') {
    const planar = y * y + z * z;
    if (planar < SINGULAR) return [0, 1, 0];  // +-X: no side in the plane
    const p = [0, y / Math.sqrt(planar), z / Math.sqrt(planar)];
    const cos = Math.cos(limit.angle);
    if (!(p[1] < cos)) return p;
    return [0, cos, p[2] < 0 ? -Math.sin(limit.angle) : Math.sin(limit.angle)];
  }
  const planar = y * y + z * z;
  let pitch = planar < SINGULAR ? 0 : Math.atan2(z, y);
  let yaw = Math.asin(Math.min(1, Math.max(-1, x)));
  let moved = false;
  if (Math.abs(pitch) > limit.pitch) { pitch = Math.sign(pitch) * limit.pitch; moved = true; }
  if (Math.abs(yaw) > limit.yaw) { yaw = Math.sign(yaw) * limit.yaw; moved = true; }
  if (!moved) return d;
  return [Math.sin(yaw), Math.cos(yaw) * Math.cos(pitch), Math.cos(yaw) * Math.sin(pitch)];
}

/** Moves `p` out of (or, inside, into) one collider in the world; returns the new point or null. */
function push(collider, world, p, hitRadius) {
  const { shape } = collider;
  // Radii scale with the collider node's largest axis scale (1 in the pack, up to float rounding).
  const nodeScale = Math.max(...[0, 4, 8].map((k) => Math.hypot(world[k], world[k + 1], world[k + 2])));
  if (shape.kind === 'plane') {
    const point = transformPoint(world, shape.offset);
    const n = transformVector(world, shape.normal);
    const normal = scale(n, 1 / length(n));
    const height = dot(sub(p, point), normal);
    return height < hitRadius ? add(p, scale(normal, hitRadius - height)) : null;
  }
  const a = transformPoint(world, shape.offset);
  let closest = a;
  if (shape.kind === 'capsule') {
    const b = transformPoint(world, shape.tail);
    const ab = sub(b, a);
    const t = Math.min(1, Math.max(0, dot(sub(p, a), ab) / dot(ab, ab)));
    closest = add(a, scale(ab, t));
  }
  const away = sub(p, closest);
  const distance = length(away);
  if (!(distance > MIN_LENGTH)) throw new Error('a tail on a collider\'s center: not used by the pack');
  if (shape.inside) {
    const reach = shape.radius * nodeScale - hitRadius;
    return distance > reach ? add(closest, scale(away, reach / distance)) : null;
  }
  const reach = shape.radius * nodeScale + hitRadius;
  return distance < reach ? add(closest, scale(away, reach / distance)) : null;
}

/**
 * One avatar's simulation of a rig from buildVrmRig, with the fixed-step rule of the ADR reference
 * (accumulator, substep cap, drivers interpolated across a frame's steps). `frame(dt, drivers)`
 * takes the world matrices of the rig's drivers (a Map node -> matrix) and returns every joint's
 * local rotation; `pushes` and `limited` count what the colliders and limits did.
 */
export class VrmReferenceInstance {
  constructor(rig, { stepHz = 60, maxSubsteps = 4 } = {}) {
    this.rig = rig;
    this.h = 1 / stepHz;
    this.maxSubsteps = maxSubsteps;
    this.accumulator = 0;
    this.seeded = false;
    this.current = rig.joints.map(() => null);
    this.previous = rig.joints.map(() => null);
    this.rotations = rig.joints.map((j) => j.restR);
    this.pushes = 0;
    this.limited = 0;
  }

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
      if (seedOnly) {
        this.current[j] = this.previous[j] = toCenter(add(head, restOffset));
        world.push(restWorld);
        return;
      }
      if (!(len > MIN_LENGTH)) throw new Error('a zero-length bone: not used by the pack');
      const p = joint.params;
      const axis = scale(joint.tailLocal, 1 / length(joint.tailLocal));
      // Limit space: the rest world rotation, +Y onto the bone axis (-Y: half a turn about X), the
      // limit's rotation.
      let frame = null;
      if (joint.limit) {
        const toAxis = axis[0] === 0 && axis[1] === -1 && axis[2] === 0 ? [1, 0, 0, 0] : rotationBetween([0, 1, 0], axis);
        frame = qmul(qmul(rotationOf(restWorld), toAxis), joint.limit.rotation);
      }
      const toLength = (q) => { const o = sub(q, head); return add(head, scale(o, len / length(o))); };
      const limit = (q) => {
        if (!frame) return q;
        const o = sub(q, head);
        const d = qrotate(qinverse(frame), scale(o, 1 / length(o)));
        const limited = limitDirection(joint.limit, d);
        if (limited === d) return q;
        this.limited++;
        return add(head, scale(qrotate(frame, limited), len));
      };
      const cur = this.current[j];
      const inertia = scale(sub(cur, this.previous[j]), 1 - p.drag);
      let next = fromCenter(add(cur, inertia));
      next = add(next, scale(scale(restOffset, 1 / len), p.stiffness * h), scale(p.gravityDir, p.gravityPower * h));
      next = limit(toLength(next));
      for (const c of joint.colliders) {
        const pushed = push(this.rig.colliders[c], drivers.get(this.rig.colliders[c].node), next, p.hitRadius);
        if (!pushed) continue;
        this.pushes++;
        next = limit(toLength(pushed));
      }
      this.previous[j] = cur;
      this.current[j] = toCenter(next);
      const localDir = transformVector(invert(linearOnly(restWorld)), sub(next, head));
      const rotation = qnormalize(qmul(joint.restR, rotationBetween(axis, scale(localDir, 1 / length(localDir)))));
      this.rotations[j] = rotation;
      world.push(mmul(parent, trsMatrix({ translation: joint.restT, rotation, scale: joint.restS })));
    });
  }

  /** Advances by one frame; returns the joints' local rotations. */
  frame(dt, driverWorld) {
    const poses = new Map(this.rig.drivers.map((d) => [d, driverWorld.get(d)]));
    if (!this.seeded) {
      this.previousPoses = poses;
      this.run(poses, 0, true);
      this.seeded = true;
    }
    const h = this.h;
    const frameStart = this.accumulator;
    this.accumulator += dt;
    const crossed = Math.floor((this.accumulator + h * 1e-6) / h);
    const dropped = crossed > this.maxSubsteps;
    const steps = dropped ? this.maxSubsteps : crossed;
    for (let i = 0; i < steps; i++) {
      const t = Math.min(1, Math.max(0, dropped ? (i + 1) / steps : ((i + 1) * h - frameStart) / dt));
      this.run(new Map(this.rig.drivers.map((d) => [d, ReferenceInstance.blend(this.previousPoses.get(d), poses.get(d), t)])), h, false);
    }
    this.accumulator = dropped ? 0 : Math.max(0, this.accumulator - steps * h);
    this.previousPoses = poses;
    this.lastSteps = steps;
    return this.rotations;
  }
}
