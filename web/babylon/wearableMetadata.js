// The spring-bone metadata registerWearable accepts, turned into what sb.loadRig takes.
//
// Three shapes, told apart by keys no bone entry can have (an entry is keyed by a node name that
// contains "springbone"; none of `models`, `version`, `entity`, `contentHash`, `glb` does):
//
// 1. a models entry, node name -> { stiffness, gravityPower, gravityDir, drag, center, isRoot }:
//    what Decentraland's preview resolves and passes (`springBones.models[hash]`);
// 2. the whole `data.springBones` ({ version, models }), which a page may pass by mistake for the
//    entry: the entry under `itemId` when there is one (an item id that is the content hash of
//    the main file), else its only entry; with several entries and none under `itemId` (the
//    preview's item id is a URN) the container alone cannot tell which is this GLB's, so no entry
//    is taken and the result carries a `springbones-ambiguous` problem that says so;
// 3. { springBones, entity, bodyShape } | { springBones, contentHash } | { springBones, glb }
//    with any other option of loadRig (colliders, limits, hitRadius, ...) and `instance`
//    (createInstance's options): the three.js loader plugin's option object. Everything but
//    springBones and instance goes to loadRig as it is, which checks it (web/wearable/rig_life.js);
//    `glb` is hashed once the module is there (the rig is read from the container's nodes).
//
// Every shape ends as { springBones, options, instance, key, problem? }: `key` is the models key the rig
// reads, under which updateParams later writes its entries; `problem` ({ code, facts }) is the
// diagnostic (web/wearable/diagnostics.js) the simulation reports for a shape it could not resolve.

import { entryAsSpringBones } from '../wearable/wearable_entry.js';

const kWholeKeys = ['models', 'version'];
const kOptionKeys = ['entity', 'contentHash', 'glb'];

const isObject = (value) => value !== null && typeof value === 'object' && !Array.isArray(value);
const has = (object, key) => Object.prototype.hasOwnProperty.call(object, key);

/**
 * Resolves registerWearable's fourth argument. Throws a TypeError for a value of none of the shapes.
 */
export function resolveMetadata(itemId, input) {
  const key = String(itemId);
  if (input === undefined || input === null) return { springBones: null, options: { contentHash: key }, key };
  if (!isObject(input)) {
    throw new TypeError('registerWearable: springBonesParams must be a models entry, a springBones object or { springBones, ...hash options }');
  }
  if (kOptionKeys.some((k) => has(input, k)) || (has(input, 'springBones') && isObject(input.springBones) && has(input.springBones, 'models'))) {
    const { springBones = null, instance, ...options } = input;
    if (options.glb === undefined && options.contentHash === undefined && options.entity === undefined && options.bodyShape === undefined) {
      options.contentHash = key;
    }
    return { springBones, options, instance, key: options.contentHash ?? null };
  }
  if (kWholeKeys.some((k) => has(input, k))) return resolveWhole(key, input);
  return { springBones: entryAsSpringBones(key, input), options: { contentHash: key }, key };
}

/** The whole springBones as registerWearable's argument: its entry under itemId, or its only one. */
function resolveWhole(itemId, springBones) {
  const models = springBones.models;
  // Not an object: loadRig's own error (metadata-invalid) or warning (models-missing) says so.
  if (!isObject(models) || has(models, itemId)) return { springBones, options: { contentHash: itemId }, key: itemId };
  const keys = Object.keys(models);
  if (keys.length === 1) return { springBones, options: { contentHash: keys[0] }, key: keys[0] };
  if (keys.length === 0) return { springBones, options: { contentHash: itemId }, key: itemId };
  return { springBones: null, options: { contentHash: itemId }, key: itemId, problem: { code: 'springbones-ambiguous', facts: { keys } } };
}
