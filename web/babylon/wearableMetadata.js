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
//    (plus loadRig's `colliders` and `hitRadius`): loadRig's own choice of entry, as the
//    three.js loader plugin takes it. `glb` is kept as it is: the rig is read from the container's
//    nodes, not from the bytes, so the simulation hashes them (sb.contentHash) once the module is
//    there (rigOptions below).
//
// Every shape ends as { springBones, options, key, problem? }: `key` is the models key the rig
// reads, under which updateParams later writes its entries; `problem` ({ code, message }) is what
// the simulation reports for a shape it could not resolve.

const kWholeKeys = ['models', 'version'];
const kOptionKeys = ['entity', 'contentHash', 'glb'];
const kPassThrough = ['colliders', 'hitRadius', 'jumpDistance', 'jumpAngle'];

const isObject = (value) => value !== null && typeof value === 'object' && !Array.isArray(value);
const has = (object, key) => Object.prototype.hasOwnProperty.call(object, key);

/** The models entry `params` for updateParams, under `key`, as a whole springBones. */
export function entryAsSpringBones(key, params) {
  return { version: 1, models: { [key]: params } };
}

/** loadRig's options for the rig of the container's nodes: `glb` becomes its content hash. */
export function rigOptions(sb, options) {
  if (options.glb === undefined) return options;
  const { glb, ...rest } = options;
  return { ...rest, contentHash: sb.contentHash(glb) };
}

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
    const options = {};
    for (const k of kPassThrough) if (input[k] !== undefined) options[k] = input[k];
    if (input.glb !== undefined) {
      options.glb = input.glb;
    } else if (input.contentHash !== undefined) {
      options.contentHash = input.contentHash;
    } else if (input.entity !== undefined || input.bodyShape !== undefined) {
      options.entity = input.entity;
      options.bodyShape = input.bodyShape;
    } else {
      options.contentHash = key;
    }
    return { springBones: input.springBones ?? null, options, key: options.contentHash ?? null };
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
  const shown = keys.slice(0, 4).map((k) => JSON.stringify(k)).join(', ') + (keys.length > 4 ? ', ...' : '');
  return {
    springBones: null,
    options: { contentHash: itemId },
    key: itemId,
    problem: {
      code: 'springbones-ambiguous',
      message: `the whole springBones was passed with ${keys.length} models (${shown}) and none is keyed by the item id, so no entry is taken and nothing moves. Fix: pass the entry, springBones.models[hash] with hash the last segment of the main file's URL (as Decentraland's preview does), or { springBones, contentHash: hash }.`,
    },
  };
}
