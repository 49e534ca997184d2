// The avatar's bones for loadRig's 'dcl-body' preset, the same under both adapters: a wearable's
// GLB carries only the bones its mesh is skinned to (a hair: Hips to Head), so the body's shapes
// are measured on the bones of the avatar it is worn on (docs/semantics.md, "Body colliders").
//
// Each engine reads its avatar's skins (three.js: skeleton.boneInverses; Babylon: each bone's
// inverted absolute transform, which its glTF loader sets from the file's inverse bind matrices)
// and hands the inverse bind matrices here as they are, in the glTF's space. The bind pose is the
// rest pose, whatever the avatar is playing when the wearable is put on; the inverse of a joint's
// inverse bind matrix is its rest world matrix in the avatar file's scene, where every
// Decentraland avatar faces +Z (the preset's "across" is that scene's X).
//
// withAvatarBones is the one place an adapter's loadRig options take the avatar's bones: when the
// core can put them on an instance instead, this is what changes.

/**
 * Whether the adapter should measure the body's shapes on the avatar: the options ask for the
 * 'dcl-body' preset and the caller gave no avatarBones of its own (those win).
 */
export function measuresOnAvatar(options) {
  return options?.colliders === 'dcl-body' && options.avatarBones === undefined;
}

/**
 * loadRig's options with the avatar's bones (restBonesFromInverseBinds) when measuresOnAvatar,
 * else the options unchanged (also for `bones` null: no avatar found, the GLB's bones measure).
 */
export function withAvatarBones(options, bones) {
  return bones && measuresOnAvatar(options) ? { ...options, avatarBones: bones } : options;
}

/**
 * The avatar's bones as loadRig's avatarBones: name -> rest world matrix (16 numbers,
 * column-major), from `joints`, an iterable of { name, inverseBind } with inverseBind the joint's
 * inverse bind matrix (16 numbers, column-major, glTF space). The first joint of each name counts
 * (an avatar's skins share their armature); a matrix that is not an invertible affine transform
 * of finite numbers is passed over, so its bone counts as missing. Null when no joint is left.
 */
export function restBonesFromInverseBinds(joints) {
  const bones = {};
  let count = 0;
  for (const { name, inverseBind } of joints) {
    if (typeof name !== 'string' || name === '' || Object.prototype.hasOwnProperty.call(bones, name)) continue;
    const rest = invertAffine(inverseBind);
    if (rest === null) continue;
    bones[name] = rest;
    count++;
  }
  return count > 0 ? bones : null;
}

/**
 * A key that is equal for two avatars with the same bones at the same rest pose (a crowd of
 * clones, every avatar of one body shape): a rig measured on one serves them all.
 */
export function avatarBonesKey(bones) {
  return JSON.stringify(Object.keys(bones).sort().map((name) => [name, Array.from(bones[name])]));
}

/** The inverse of a column-major affine 4x4 matrix, or null (not affine, singular, not finite). */
function invertAffine(m) {
  if (!m || m.length !== 16) return null;
  for (let i = 0; i < 16; i++) if (!Number.isFinite(m[i])) return null;
  // Babylon recomputes the matrices it keeps from the file's, so the last row may be off by rounding.
  if (Math.abs(m[3]) > 1e-6 || Math.abs(m[7]) > 1e-6 || Math.abs(m[11]) > 1e-6 || Math.abs(m[15] - 1) > 1e-6) return null;
  const [a, b, c, , d, e, f, , g, h, i] = m;
  // Columns (a b c), (d e f), (g h i): the inverse of the 3x3 part by cofactors.
  const c0 = e * i - f * h;
  const c1 = f * g - d * i;
  const c2 = d * h - e * g;
  const det = a * c0 + b * c1 + c * c2;
  if (!(Math.abs(det) > 1e-30)) return null;
  const s = 1 / det;
  const r = [
    c0 * s, (c * h - b * i) * s, (b * f - c * e) * s, 0,
    c1 * s, (a * i - c * g) * s, (c * d - a * f) * s, 0,
    c2 * s, (b * g - a * h) * s, (a * e - b * d) * s, 0,
    0, 0, 0, 1,
  ];
  const [tx, ty, tz] = [m[12], m[13], m[14]];
  r[12] = -(r[0] * tx + r[4] * ty + r[8] * tz);
  r[13] = -(r[1] * tx + r[5] * ty + r[9] * tz);
  r[14] = -(r[2] * tx + r[6] * ty + r[10] * tz);
  return r;
}
