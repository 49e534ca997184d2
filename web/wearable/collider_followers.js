// Colliders that follow objects of the engine's scene, for both adapters' setColliders: the page
// hands a collider's `node` as a name (a rig driver, an avatar bone, as loadRig takes it) or as the
// engine's object itself (three.js: an Object3D; Babylon: a TransformNode), a hat or another
// wearable's node. instance.setColliders takes names only: a name that is no rig driver becomes a
// frame whose world matrix the page writes each frame (docs/semantics.md, "Colliders at run
// time"). So each object gets a frame name of its own here, and after the call every frame is
// matched to the object it follows; the engine file then copies that object's world matrix into
// frameMatrices at the frame's slot, every frame, after the drivers'.
//
// Engine-free: the engine file says what an object of its scene is, what it is called, and how a
// name is found in its scene; the words of the errors and warnings are the same in both engines.

import { diagnostic } from './diagnostics.js';

const kNodeKinds = 'a node name (a string) or an object of the engine\'s scene (three.js: an Object3D; Babylon: a TransformNode)';

/** A value as an error message shows it, without the engine's own object dump. */
const describe = (value) => (value === null || typeof value !== 'object' ? String(value) : Array.isArray(value) ? 'an array' : 'an object of another kind');

/**
 * What instance.setColliders takes for `colliders` (an array, 'dcl-body' or null, as loadRig's
 * option, where a collider's `node` may also be an object of the engine's scene), and
 * `followed`: frame name -> the object it follows. An object gets its own name, unless that is a
 * rig driver's, a name another collider gives as a string, or another object's: then the name
 * with " #2", " #3"... The same object twice is one frame. What is not an array is handed on as it
 * is (the instance checks it); a collider's node that is neither a string nor an object of the
 * scene is a TypeError naming it (`setColliders: colliders[1].node`).
 *
 * engine: { isObject(value): whether value is an object of the scene, nameOf(object): its name,
 *           driverNames: the rig's drivers' names }
 */
export function collidersWithFrames(where, colliders, { isObject, nameOf, driverNames }) {
  const followed = new Map();
  if (!Array.isArray(colliders)) return { colliders, followed };
  const taken = new Set(driverNames);
  for (const c of colliders) if (typeof c?.node === 'string') taken.add(c.node);
  const names = new Map();  // object -> its frame name
  const frameName = (object) => {
    if (names.has(object)) return names.get(object);
    const base = nameOf(object) || 'object';
    let name = base;
    for (let k = 2; taken.has(name); k++) name = `${base} #${k}`;
    taken.add(name);
    names.set(object, name);
    followed.set(name, object);
    return name;
  };
  const out = colliders.map((c, i) => {
    if (c === null || typeof c !== 'object' || Array.isArray(c) || typeof c.node === 'string') return c;
    if (!isObject(c.node)) throw new TypeError(`${where}: colliders[${i}].node must be ${kNodeKinds}, got ${describe(c.node)}`);
    return { ...c, node: frameName(c.node) };
  });
  return { colliders: out, followed };
}

/**
 * instance.setColliders' options with the avatar's bones the adapter measured (`avatarBones`, null
 * when it found none) for 'dcl-body', unless the page gave its own; else the options unchanged.
 */
export function withMeasuredBones(colliders, options, avatarBones) {
  if (colliders !== 'dcl-body' || !avatarBones) return options;
  if (options !== undefined && (options === null || typeof options !== 'object' || options.avatarBones !== undefined)) return options;
  return { ...options, avatarBones };
}

/**
 * The object each of the instance's frames follows, in frameNames' order: the object given for
 * it, else what `findByName` finds of that name in the engine's scene (an avatar bone of
 * 'dcl-body' on a rig loaded without it, a node named as a string), else null. `missing`: the
 * names nothing was found for.
 */
export function frameFollowers(frameNames, followed, findByName) {
  const missing = [];
  const objects = frameNames.map((name) => {
    const object = followed.get(name) ?? findByName(name) ?? null;
    if (object === null) missing.push(name);
    return object;
  });
  return { objects, missing };
}

/**
 * The diagnostics of a setColliders call: the instance's warnings (their codes and messages, with
 * a fix), and collider-not-followed for frames no object was found for.
 */
export function colliderDiagnostics(warnings, missing) {
  const found = warnings.map((w) => diagnostic(w.code, { coreMessage: w.message }, w.path ?? ''));
  if (missing.length > 0) found.push(diagnostic('collider-not-followed', { names: missing }));
  return found;
}
