// The rig's life, the same under both adapters: loaded with the caller's options handed to loadRig
// as they are (loadRig checks them: an option it does not know is its TypeError, so a `limits`
// or `colliders` given to an adapter reaches the simulation or is refused, never dropped); rebuilt
// for a live edit of the models entry; and each rebuild's instance taking its predecessor's
// motion over, so an edit neither pops nor restarts the chains.

import { entryAsSpringBones, mergeEntry, modelsEntry } from './wearable_entry.js';

/**
 * The options an adapter takes besides loadRig's. `glb` is the bytes being parsed, which names the
 * models entry by their content hash: a loader hook never sees the bytes it parsed, so the caller
 * hands them over and the adapter hashes them once the module is there.
 */
export const kAdapterOptions = Object.freeze(['sb', 'springBones', 'glb', 'onWarning', 'instance']);

/** The adapter's options without its own keys: what goes to loadRig, unchanged. */
export function loadRigOptionsOf(options) {
  const out = {};
  for (const [key, value] of Object.entries(options)) if (!kAdapterOptions.includes(key) || key === 'glb') out[key] = value;
  return out;
}

/** loadRig's options with `glb` replaced by its content hash (sb.contentHash). */
export function withGlbHashed(sb, options) {
  if (options.glb === undefined) return options;
  const { glb, ...rest } = options;
  return rest.contentHash === undefined && rest.entity === undefined ? { ...rest, contentHash: sb.contentHash(glb) } : rest;
}

/** The rig of `gltf` (a parsed glTF document) for these springBones and loadRig options. */
export function loadWearableRig(sb, gltf, springBones, options) {
  return sb.loadRig(gltf, springBones, withGlbHashed(sb, options));
}

/**
 * The springBones and loadRig options of a live edit: `params` (node name -> parameters, the
 * whole entry) merged over the entry under `key` (mergeEntry), named by its key alone.
 */
export function liveEdit(springBones, key, options, params) {
  const edited = entryAsSpringBones(key, mergeEntry(modelsEntry(springBones, key), params));
  const { entity, bodyShape, glb, ...rest } = options;
  return { springBones: edited, options: { ...rest, contentHash: key } };
}

/**
 * Hands `previous`'s motion to `instance` (instance.carryFrom): `writeDrivers(instance)` first
 * writes the drivers' current world matrices, the pose `previous` last stepped under. Joints both
 * rigs simulate keep moving; new ones start from where they are drawn. Nothing for a previous
 * instance that is gone.
 */
export function carryMotion(instance, previous, writeDrivers) {
  if (!previous || previous.disposed) return;
  writeDrivers(instance);
  instance.carryFrom(previous);
}

/**
 * Refuses an option an adapter's call cannot honour, with a TypeError: loadRig's options (limits,
 * colliders, ...) shape the rig, which every avatar wearing the wearable shares, so given where
 * only one avatar is worn they would otherwise go nowhere, silently.
 */
export function checkOptionKeys(where, options, allowed) {
  for (const key of Object.keys(options)) {
    if (!allowed.includes(key)) {
      throw new TypeError(`${where}: unknown option ${key} (expected ${allowed.join(', ')}); loadRig's options (limits, colliders, ...) ` +
        'shape the rig every avatar shares: give them to the SpringBonesLoaderPlugin, registerWearable or loadRig');
    }
  }
}
