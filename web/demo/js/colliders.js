// The avatar's colliders: the core's 'dcl-body' preset (a head sphere and capsules for the neck,
// chest, belly, shoulders and upper arms, measured on the avatar's own bones, avatarRestBones;
// docs/semantics.md, "Body colliders"), handed to sb.loadRig next to the wearable's metadata (the
// GLB is not touched), and a wireframe drawing of a rig's colliders.
import * as THREE from 'three';

/** loadRig's colliders option for the avatar's body. */
export const AVATAR_COLLIDERS = 'dcl-body';

/** Radius of every joint's tail against the colliders, metres (world units). */
export const AVATAR_HIT_RADIUS = 0.01;

const kSegments = 32;

/** Line-segment points (pairs) of an arc around `c` in the plane of unit vectors `u`, `v`,
 *  from angle a0 to a1 (radians). */
function arcPoints(c, u, v, radius, a0, a1, out) {
  const n = Math.max(2, Math.round((kSegments * (a1 - a0)) / (2 * Math.PI)));
  for (let i = 0; i < n; i++) {
    for (const k of [i, i + 1]) {
      const a = a0 + ((a1 - a0) * k) / n;
      const cu = Math.cos(a) * radius;
      const sv = Math.sin(a) * radius;
      out.push(c.x + u.x * cu + v.x * sv, c.y + u.y * cu + v.y * sv, c.z + u.z * cu + v.z * sv);
    }
  }
}

const X = new THREE.Vector3(1, 0, 0);
const Y = new THREE.Vector3(0, 1, 0);
const Z = new THREE.Vector3(0, 0, 1);

/** A sphere: three great circles. */
function spherePoints(c, radius, out) {
  arcPoints(c, X, Y, radius, 0, 2 * Math.PI, out);
  arcPoints(c, Y, Z, radius, 0, 2 * Math.PI, out);
  arcPoints(c, Z, X, radius, 0, 2 * Math.PI, out);
}

/** A capsule: a ring at each end of the axis, a half circle capping each end in two planes
 *  through the axis, and four lines along it. */
function capsulePoints(a, b, radius, out) {
  const axis = new THREE.Vector3().subVectors(b, a).normalize();
  const u = new THREE.Vector3().crossVectors(axis, Math.abs(axis.y) < 0.9 ? Y : X).normalize();
  const v = new THREE.Vector3().crossVectors(axis, u);
  const back = axis.clone().negate();
  for (const [c, out_] of [[a, back], [b, axis]]) {
    arcPoints(c, u, v, radius, 0, 2 * Math.PI, out);
    arcPoints(c, u, out_, radius, 0, Math.PI, out);   // from +u over the cap to -u
    arcPoints(c, v, out_, radius, 0, Math.PI, out);
  }
  for (const d of [u, v, u.clone().negate(), v.clone().negate()]) {
    out.push(a.x + d.x * radius, a.y + d.y * radius, a.z + d.z * radius, b.x + d.x * radius, b.y + d.y * radius, b.z + d.z * radius);
  }
}

/**
 * Wireframes of a rig's colliders, each a child of the object that carries it (so it follows the
 * bone with no per-frame work). `objectOf(driverIndex)` gives that object, or null (not drawn).
 */
export class ColliderHelper {
  constructor(colliders, objectOf) {
    this.material = new THREE.LineBasicMaterial({ color: 0x5fd7ff, transparent: true, opacity: 0.7, depthTest: false, depthWrite: false, toneMapped: false });
    this.lines = [];
    for (const c of colliders) {
      const parent = objectOf(c.driver);
      if (!parent) continue;
      const points = [];
      const a = new THREE.Vector3().fromArray(c.offset);
      if (c.shape === 'capsule') capsulePoints(a, new THREE.Vector3().fromArray(c.tail), c.radius, points);
      else spherePoints(a, c.radius, points);
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.Float32BufferAttribute(points, 3));
      const lines = new THREE.LineSegments(geometry, this.material);
      lines.name = `collider:${c.node}`;
      lines.renderOrder = 998;
      lines.frustumCulled = false;
      parent.add(lines);
      this.lines.push(lines);
    }
  }

  setVisible(visible) {
    for (const l of this.lines) l.visible = visible;
  }

  dispose() {
    for (const l of this.lines) {
      l.removeFromParent();
      l.geometry.dispose();
    }
    this.lines = [];
    this.material.dispose();
  }
}
