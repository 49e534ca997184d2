// Babylon's world against the glTF's. springbones takes drivers, gravity and colliders in the
// glTF's space (right-handed, +Y up), as three.js does. Babylon's scenes are left-handed unless
// `scene.useRightHandedSystem`; its glTF loader then puts the file under a `__root__` node turned
// 180 degrees about Y and scaled by -1 in Z, which together map a point (x, y, z) of the file to
// (-x, y, z) of Babylon's world. So the glTF's world is Babylon's world mirrored in X: a node's
// world matrix in glTF space is diag(-1, 1, 1) times Babylon's. In a right-handed scene the loader
// adds no conversion and the two spaces are the same.
//
// Babylon stores a matrix for row vectors, row-major; read as a column-major matrix for column
// vectors (the glTF and springbones convention) it is the same 16 numbers. Mirroring in X negates
// the first row of that column-major matrix: elements 0, 4, 8 and 12.

/** True when the scene's world is the mirror of the glTF's (a left-handed Babylon scene). */
export function isMirroredScene(scene) {
  return !scene.useRightHandedSystem;
}

/**
 * Copies a Babylon world matrix (its `.m`) into `out` at `offset` as a glTF-space world matrix.
 * Allocation-free: the per-frame driver copy.
 */
export function copyWorldMatrix(m, out, offset, mirrored) {
  const s = mirrored ? -1 : 1;
  out[offset] = s * m[0]; out[offset + 1] = m[1]; out[offset + 2] = m[2]; out[offset + 3] = m[3];
  out[offset + 4] = s * m[4]; out[offset + 5] = m[5]; out[offset + 6] = m[6]; out[offset + 7] = m[7];
  out[offset + 8] = s * m[8]; out[offset + 9] = m[9]; out[offset + 10] = m[10]; out[offset + 11] = m[11];
  out[offset + 12] = s * m[12]; out[offset + 13] = m[13]; out[offset + 14] = m[14]; out[offset + 15] = m[15];
}
