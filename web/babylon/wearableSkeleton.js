// What springbones needs from a Babylon.js AssetContainer: its nodes (names, hierarchy, rest
// transforms) as a glTF document that sb.loadRig reads like the file itself (handed over as an
// object: nothing is stringified), and the Babylon node behind each glTF node index of it.
//
// Babylon's glTF loader gives every glTF node a TransformNode (a Mesh for a node with a mesh)
// whose position / rotationQuaternion / scaling are the file's own local values: the conversion
// from the file's right-handed space to a left-handed scene is done once, by the `__root__` node
// it puts above the file's scene. So the local transforms read here are the glTF's, and the
// glTF's world space is the Babylon world seen through that conversion (see handedness.js).
//
// The document is made once, at registration, while the wearable is in its rest pose (as loaded,
// before an animation moves it); every later rig of the same wearable (updateParams) is built from
// that same document, so an edit never takes the animated pose for the rest pose.

/** Every TransformNode of the container (meshes included), each once, in the container's order. */
function containerNodes(container) {
  const nodes = [];
  const seen = new Set();
  for (const list of [container.transformNodes, container.meshes]) {
    for (const node of list ?? []) {
      if (node && !seen.has(node)) {
        seen.add(node);
        nodes.push(node);
      }
    }
  }
  return nodes;
}

/** The node's local rotation as [x, y, z, w] (from its Euler angles if it has no quaternion). */
function localRotation(node) {
  const q = node.rotationQuaternion ?? node.rotation.toQuaternion();
  return [q.x, q.y, q.z, q.w];
}

const finiteOr = (values, fallback) => (values.every(Number.isFinite) ? values : fallback);

/**
 * Reads the container's node hierarchy. Returns { nodes, gltf }: nodes[i] is the Babylon node
 * of glTF node i of gltf (a glTF document with only nodes and one scene). A node
 * whose parent is outside the container (the loader's `__root__` has none) is a top-level node
 * of the text, with an identity transform: its world matrix is what the simulation reads each
 * frame (as a driver), never its rest values.
 */
export function readWearableSkeleton(container) {
  if (container === null || typeof container !== 'object' || !Array.isArray(container.transformNodes)) {
    throw new TypeError('registerWearable: container must be a Babylon AssetContainer (with transformNodes and meshes)');
  }
  const nodes = containerNodes(container);
  const index = new Map(nodes.map((node, i) => [node, i]));
  const gltfNodes = nodes.map((node) => {
    const entry = { name: String(node.name ?? '') };
    const children = [];
    for (const child of node.getChildren(undefined, true)) {
      const i = index.get(child);
      if (i !== undefined) children.push(i);
    }
    if (children.length > 0) entry.children = children;
    if (index.has(node.parent)) {
      const p = node.position;
      const s = node.scaling;
      entry.translation = finiteOr([p.x, p.y, p.z], [0, 0, 0]);
      entry.rotation = finiteOr(localRotation(node), [0, 0, 0, 1]);
      entry.scale = finiteOr([s.x, s.y, s.z], [1, 1, 1]);
    }
    return entry;
  });
  const roots = [];
  nodes.forEach((node, i) => {
    if (!index.has(node.parent)) roots.push(i);
  });
  const gltf = { asset: { version: '2.0' }, scene: 0, scenes: [{ nodes: roots }], nodes: gltfNodes };
  return { nodes, gltf };
}
