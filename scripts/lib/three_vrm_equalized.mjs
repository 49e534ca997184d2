// @pixiv/three-vrm-springbone 3.5.5 with two of the README's documented differences made equal,
// for runs that compare its rotations with ours:
//  - the bone length: stock 3.5.5 reads it from the child's world matrix as it was at the end of
//    the previous frame; useExactBoneLength() refreshes the child's world matrix first (the child's
//    position only depends on the joint's world matrix and the child's translation), the fixed
//    length the VRM spec and springbones use;
//  - collider radii: three-vrm uses them as authored, springbones scales them with the collider
//    node's world scale; scaleColliderRadii(manager) makes three-vrm scale them too.
import { VRMSpringBoneJoint } from '@pixiv/three-vrm-springbone';

const stockLength = VRMSpringBoneJoint.prototype._calcWorldSpaceBoneLength;
function currentLength() {
  // (updateWorldMatrix would not do: three r187 skips it unless the local matrix was just rebuilt.)
  if (this.child) this.child.matrixWorld.multiplyMatrices(this.child.parent.matrixWorld, this.child.matrix);
  stockLength.call(this);
}

/** Exact (true) or stock (false) bone lengths for every VRMSpringBoneJoint from now on. */
export function useExactBoneLength(exact) {
  VRMSpringBoneJoint.prototype._calcWorldSpaceBoneLength = exact ? currentLength : stockLength;
}

/** Every sphere and capsule of the manager's colliders gets its radius times its largest world scale. */
export function scaleColliderRadii(manager) {
  for (const collider of manager.colliders) {
    const shape = collider.shape;
    if (shape.radius === undefined) continue;
    const authored = shape.radius;
    const original = shape.calculateCollision.bind(shape);
    shape.calculateCollision = (matrix, ...rest) => {
      const e = matrix.elements;
      const scale = Math.max(Math.hypot(e[0], e[1], e[2]), Math.hypot(e[4], e[5], e[6]), Math.hypot(e[8], e[9], e[10]));
      shape.radius = authored * scale;
      try {
        return original(matrix, ...rest);
      } finally {
        shape.radius = authored;
      }
    };
  }
}
