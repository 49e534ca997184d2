// The avatar's colliders (issue 9): a head sphere and two torso capsules on the Decentraland
// armature, handed to sb.loadRig next to the wearable's metadata (the GLB is not touched), and a
// wireframe drawing of a rig's colliders.
//
// Offsets and radii are in the bone's own space. Decentraland's `Armature` carries scale 0.01, so
// that space is in centimetres; the sample avatar's bone frames below the hips are world-aligned
// at rest (+Y up, the avatar faces +Z). Sizes follow the sample's body (scripts/make_sample_avatar.mjs):
// the skull is an ellipsoid centred 9 cm above Avatar_Head with radii 9.2 x 11.2 x 10.2 cm, the
// chest one 5 cm above Avatar_Spine2 with radii 17 x 11.5 x 11 cm. The sphere stays inside the
// hair cap and clear of the roots of every chain, so nothing starts inside it.
import * as THREE from 'three';

export const AVATAR_COLLIDERS = Object.freeze([
  Object.freeze({ node: 'Avatar_Head', offset: Object.freeze([0, 9, 1]), radius: 9.5 }),
  Object.freeze({ node: 'Avatar_Spine2', offset: Object.freeze([-6, 5, -0.5]), tail: Object.freeze([6, 5, -0.5]), radius: 11 }),
  Object.freeze({ node: 'Avatar_Spine1', offset: Object.freeze([-5, 6, 0]), tail: Object.freeze([5, 6, 0]), radius: 9.5 }),
]);

/** Radius of every joint's tail against the colliders, metres (world units). */
export const AVATAR_HIT_RADIUS = 0.01;

const kSegments = 32;

/** Line-segment points (pairs) of three great circles of a sphere of `radius` around `c`. */
function spherePoints(c, radius, out) {
  for (let axis = 0; axis < 3; axis++) {
    for (let i = 0; i < kSegments; i++) {
      for (const k of [i, i + 1]) {
        const a = (k / kSegments) * Math.PI * 2;
        const p = [c.x, c.y, c.z];
        p[(axis + 1) % 3] += radius * Math.cos(a);
        p[(axis + 2) % 3] += radius * Math.sin(a);
        out.push(...p);
      }
    }
  }
}

/** A capsule as a sphere at each end joined by four lines along the axis. */
function capsulePoints(a, b, radius, out) {
  spherePoints(a, radius, out);
  spherePoints(b, radius, out);
  const axis = new THREE.Vector3().subVectors(b, a).normalize();
  const u = new THREE.Vector3().crossVectors(axis, Math.abs(axis.y) < 0.9 ? new THREE.Vector3(0, 1, 0) : new THREE.Vector3(1, 0, 0)).normalize();
  const v = new THREE.Vector3().crossVectors(axis, u);
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
