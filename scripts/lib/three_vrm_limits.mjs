// The angle limits of VRMC_springBone_limit (1.0-draft) on @pixiv/three-vrm-springbone 3.5.5,
// which does not read them: a reference of the rules of three-vrm's pull request #1632 (its
// VRMSpringBoneLimit*.ts, not in a release), written here from those rules, for runs that compare
// it with springbones. What it follows:
//  - the limit space: the rotation of the joint's world-space initial matrix (its parent's world
//    matrix x its initial local matrix), x the shortest turn taking +Y onto the joint's bone axis (an
//    axis of exactly -Y: half a turn about X, the draft's rule), x the limit's `rotation`;
//  - the limit is applied to the tail right after inertia, stiffness and gravity (where three-vrm
//    restores the bone length) and again after each collider that moves the tail;
//  - the shapes and their singular directions as the draft's reference implementation, with the
//    PR's tolerance (sqrt of double epsilon on a squared length).
// One switch:
//  - exactRotation (default true): the PR reads the limit space's rotation with
//    Quaternion.setFromRotationMatrix, which assumes an unscaled matrix, so under a scaled parent
//    (the three example files scale their roots by 0.25) its limit space turns away from the
//    joint's. true takes the rotation of the matrix with its scale divided out, as the draft's
//    "parent world rotation x initial local rotation" and springbones do; false is the PR as written.
import * as THREE from 'three';

const kSingular = Math.sqrt(Number.EPSILON);
const _head = new THREE.Vector3();
const _dir = new THREE.Vector3();
const _m = new THREE.Matrix4();
const _pos = new THREE.Vector3();
const _scale = new THREE.Vector3();
const _push = new THREE.Vector3();
const _q = new THREE.Quaternion();
const _axisTurn = new THREE.Quaternion();

/** The limit object of a VRMC_springBone joint, as the PR reads it (specVersion "1.0-draft"), or null. */
export function jointLimitOf(joint) {
  const ext = joint?.extensions?.VRMC_springBone_limit;
  if (!ext || ext.specVersion !== '1.0-draft' || typeof ext.limit !== 'object') return null;
  const { cone, hinge, spherical } = ext.limit;
  const rotation = (shape) => new THREE.Quaternion().fromArray(shape.rotation ?? [0, 0, 0, 1]);
  const clamp = (v, max) => THREE.MathUtils.clamp(v ?? max, 0, max);
  if (cone) return { kind: 'cone', angle: clamp(cone.angle, Math.PI), rotation: rotation(cone) };
  if (hinge) return { kind: 'hinge', angle: clamp(hinge.angle, Math.PI), rotation: rotation(hinge) };
  if (spherical) {
    return {
      kind: 'spherical',
      pitch: clamp(spherical.pitch ?? spherical.phi, Math.PI),
      yaw: clamp(spherical.yaw ?? spherical.theta, Math.PI / 2),
      rotation: rotation(spherical),
    };
  }
  return null;
}

/** Keeps a unit direction in limit space inside the limit; returns whether it moved it. */
export function limitDirection(limit, d) {
  if (limit.kind === 'cone') {
    const cos = Math.cos(limit.angle);
    if (!(d.y < cos)) return false;
    const sin = Math.sqrt(1 - cos * cos);
    const horizontal2 = 1 - d.y * d.y;
    if (horizontal2 < kSingular) {
      d.set(0, cos, sin);
    } else {
      const k = sin / Math.sqrt(horizontal2);
      d.set(d.x * k, cos, d.z * k);
    }
    return true;
  }
  if (limit.kind === 'hinge') {
    const projected2 = d.y * d.y + d.z * d.z;
    if (projected2 < kSingular) {
      d.set(0, 1, 0);
      return true;
    }
    let moved = false;
    if (d.x !== 0) {
      const k = 1 / Math.sqrt(projected2);
      d.set(0, d.y * k, d.z * k);
      moved = true;
    }
    const cos = Math.cos(limit.angle);
    if (d.y < cos) {
      const sin = Math.sqrt(1 - cos * cos);
      d.set(0, cos, d.z < 0 ? -sin : sin);
      moved = true;
    }
    return moved;
  }
  let pitch = d.y * d.y + d.z * d.z < kSingular ? 0 : Math.atan2(d.z, d.y);
  if (d.z === 0 && d.y < 0) pitch = Math.PI;
  let yaw = Math.asin(THREE.MathUtils.clamp(d.x, -1, 1));
  let moved = false;
  if (Math.abs(pitch) > limit.pitch) {
    pitch = limit.pitch * Math.sign(pitch);
    moved = true;
  }
  if (Math.abs(yaw) > limit.yaw) {
    yaw = limit.yaw * Math.sign(yaw);
    moved = true;
  }
  if (moved) d.set(Math.sin(yaw), Math.cos(yaw) * Math.cos(pitch), Math.cos(yaw) * Math.sin(pitch));
  return moved;
}

/**
 * Gives every joint of `manager` whose node (by index, `nodes`) has a limit in the glTF JSON `json`
 * the PR's limit. Returns the count of directions it moved, per kind, so a run is known to reach
 * the limits.
 */
export function applyLimits(manager, json, nodes, { exactRotation = true } = {}) {
  const limitOfNode = new Map();
  for (const spring of json.extensions?.VRMC_springBone?.springs ?? []) {
    spring.joints.slice(0, -1).forEach((joint) => {
      const limit = jointLimitOf(joint);
      if (limit) limitOfNode.set(nodes[joint.node], limit);
    });
  }
  const counts = { cone: 0, hinge: 0, spherical: 0 };
  for (const joint of manager.joints) {
    const limit = limitOfNode.get(joint.bone);
    if (!limit) continue;
    const axis = joint._boneAxis;
    if (axis.x === 0 && axis.y === -1 && axis.z === 0) _axisTurn.set(1, 0, 0, 0);
    else _axisTurn.setFromUnitVectors(new THREE.Vector3(0, 1, 0), axis);
    const fixed = _axisTurn.clone().multiply(limit.rotation);
    const frame = new THREE.Quaternion();
    const frameInverse = new THREE.Quaternion();
    const limitTail = (tail) => {
      _head.setFromMatrixPosition(joint.bone.matrixWorld);
      _dir.subVectors(tail, _head).normalize();
      _dir.applyQuaternion(frameInverse);
      if (!limitDirection(limit, _dir)) return;
      counts[limit.kind]++;
      tail.copy(_head).addScaledVector(_dir.applyQuaternion(frame), joint._worldSpaceBoneLength);
    };
    // three-vrm 3.5.5 calls _collision right after it puts the tail back at the bone's length: the
    // limit goes first (after inertia), then after each collider that moves the tail.
    joint._collision = function collisionWithLimit(tail) {
      _m.multiplyMatrices(this.bone.parent ? this.bone.parent.matrixWorld : new THREE.Matrix4(), this._initialLocalMatrix);
      if (exactRotation) _m.decompose(_pos, _q, _scale);
      else _q.setFromRotationMatrix(_m).normalize();
      frame.copy(_q).multiply(fixed);
      frameInverse.copy(frame).invert();
      limitTail(tail);
      for (const group of this.colliderGroups) {
        for (const collider of group.colliders) {
          const dist = collider.shape.calculateCollision(collider.colliderMatrix, tail, this.settings.hitRadius, _push);
          if (!(dist < 0)) continue;
          tail.addScaledVector(_push, -dist);
          _head.setFromMatrixPosition(this.bone.matrixWorld);
          tail.sub(_head).setLength(this._worldSpaceBoneLength).add(_head);
          limitTail(tail);
        }
      }
    };
  }
  return counts;
}
