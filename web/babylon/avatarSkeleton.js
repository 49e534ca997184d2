// The avatar a wearable is worn on, found in a Babylon scene the way Decentraland's preview builds
// one: each GLB (the body shape and every wearable) is an AssetContainer of its own, added to the
// scene, with its own copy of the armature bones it carries and its own skeleton; the preview
// tells the body shape apart by its category, which the scene does not show. The body shape's
// skin covers the whole armature (every Decentraland avatar has the same 62 bones), a wearable's
// only the bones it needs (a hair: Hips to Head). So the avatar is the skeleton of the scene with
// the most bones outside the wearable's own container, when it has more than the wearable's own.
//
// Its bones' rest pose comes from their inverse bind matrices (web/wearable/avatar_bones.js):
// Babylon's glTF loader sets each bone's inverted absolute transform from the file's, in the
// file's own space (the conversion to a left-handed scene is the `__root__` node above, not in
// them), the space the wearable's nodes are read in (wearableSkeleton.js).

import { restBonesFromInverseBinds } from '../wearable/avatar_bones.js';

const boneCount = (skeleton) => skeleton?.bones?.length ?? 0;

/**
 * The avatar's skeleton: the skeleton of `scene` with the most bones that is not one of
 * `container`'s, or null when none has more bones than the container's own (no avatar in the
 * scene yet, or the container is the avatar's): the GLB's bones then measure the shapes.
 */
export function findAvatarSkeleton(scene, container) {
  const own = new Set(container?.skeletons ?? []);
  let best = null;
  for (const skeleton of scene?.skeletons ?? []) {
    if (!own.has(skeleton) && boneCount(skeleton) > boneCount(best)) best = skeleton;
  }
  const ownMost = Math.max(0, ...[...own].map(boneCount));
  return best !== null && boneCount(best) > ownMost ? best : null;
}

/** The skeleton's bones as loadRig's `avatarBones` (name -> rest world matrix, glTF space), or null. */
export function avatarRestBones(skeleton) {
  return restBonesFromInverseBinds(skeleton.bones.map((bone) => ({
    name: bone.name,
    inverseBind: bone.getInvertedAbsoluteTransform?.()?.m ?? null,
  })));
}

/** The node that moves the skeleton's bone of that name (its linked TransformNode), or null. */
export function avatarNode(skeleton, name) {
  const bone = skeleton.bones.find((b) => b.name === name);
  return bone?.getTransformNode?.() ?? null;
}
