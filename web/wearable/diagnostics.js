// Why a worn wearable's hair does not move (or only partly), said the same way by the three.js
// adapter, the Babylon drop-in and the demo's creator panel. Each case below leaves a wearable
// drawn, with no exception, and hair that stays still: without a word the user sees a static
// ponytail and no reason. docs/diagnostics.md is the table people read; this file is the one the
// code reads, and tests/adapters/diagnostics.test.mjs holds the two together.
//
// A diagnostic is { code, message, fix, path }: `message` says what is wrong and what it does to
// the hair, `fix` what to change. Both are written once per code, here, from the facts the engine
// file found (names, the error). The engine files only find the facts: which nodes exist, which
// avatar bones matched.

import { isSpringBoneName } from './spring_bone_name.js';

const kMaxListed = 6;

/** Names, quoted, the first few and how many more. */
export function listNames(names) {
  const shown = names.slice(0, kMaxListed).map((n) => JSON.stringify(n)).join(', ');
  return names.length > kMaxListed ? `${shown} and ${names.length - kMaxListed} more` : shown;
}

const describeError = (error) => `${error?.name ?? 'Error'}${error?.code ? ` [${error.code}]` : ''}: ${error?.message ?? String(error)}`;

/** A JSON pointer token (RFC 6901). */
const pointerToken = (key) => `/${String(key).replaceAll('~', '~0').replaceAll('/', '~1')}`;

/**
 * Every code: its message and fix, each a function of the facts. The order is the order of
 * docs/diagnostics.md.
 */
export const kDiagnostics = Object.freeze({
  'module-failed': {
    message: ({ error }) => `the springbones module did not load (${describeError(error)}), so no rig is built and every wearable stays at rest`,
    fix: () => 'serve springbones_wasm.wasm beside the package\'s JavaScript (README, "Finding the .wasm"), import springbones/inline, or start the module yourself and pass it',
  },
  'rig-failed': {
    message: ({ error }) => `loadRig refused this wearable (${describeError(error)}), so it stays at rest`,
    fix: () => 'correct what the error names (the same error is on ready and .error)',
  },
  'springbones-missing': {
    message: ({ springNames }) => `no springBones was given, though the GLB has ${springNames.length} spring-bone nodes (${listNames(springNames)}), so nothing moves`,
    fix: () => 'pass the wearable\'s data.springBones (entity.metadata.data.springBones) with its hash options, or its models entry springBones.models[hash]',
  },
  'models-missing': {
    message: ({ coreMessage }) => coreMessage,
    fix: () => 'pass the wearable\'s data.springBones ({ version, models }), not the entity or one entry of it',
  },
  'model-not-found': {
    message: ({ coreMessage }) => coreMessage,
    fix: () => 'name this GLB\'s models key: contentHash (the last segment of the main file\'s URL), entity + bodyShape, or glb (its bytes)',
  },
  'springbones-ambiguous': {
    message: ({ keys }) => `the whole springBones was passed with ${keys.length} models (${listNames(keys)}) and none is keyed by the item id, so no entry is taken and nothing moves`,
    fix: () => 'pass the entry, springBones.models[hash] with hash the last segment of the main file\'s URL (as Decentraland\'s preview does), or { springBones, contentHash: hash }',
  },
  'entry-not-matched': {
    message: ({ names }) => `none of the models entry's ${names.length} names (${listNames(names)}) is a node of this GLB, so nothing moves: the entry is another file's`,
    fix: () => 'pass the entry of this GLB: springBones.models[hash] with hash the content hash of this GLB (the last segment of its URL)',
  },
  'no-chain-root': {
    message: ({ names }) => `no spring bone of the models entry has "isRoot": true (${listNames(names)} would start chains), so no chain starts and nothing moves`,
    fix: ({ names }) => `add "isRoot": true to the top spring bone of each chain: ${listNames(names)}`,
  },
  'unrooted-bones': {
    message: ({ names }) => `${listNames(names)} have entries but neither "isRoot": true nor a chain root above them, so they stay at rest while the other chains move (springbones starts a chain only at isRoot, as the standard says; Decentraland's preview class starts one at every entry)`,
    fix: ({ names }) => `add "isRoot": true to ${listNames(names)} in the models entry`,
  },
  'no-chains': {
    message: ({ springNames }) => `the rig has no chain, though the GLB has spring-bone nodes (${listNames(springNames)}), so nothing moves`,
    fix: () => 'hand the adapter the springBones the rig was loaded with (attachWearable\'s springBones option) to be told which case this is, or load the rig with this GLB\'s entry and "isRoot": true on each chain\'s top spring bone',
  },
  'bone-not-matched': {
    message: ({ bones, still, moving, colliders }) => `the avatar has no bone named ${listNames(bones)}: ` +
      [still.length > 0 ? `the chains ${listNames(still)} hang from it and do not follow the avatar's bones` : null,
        colliders.length > 0 ? `the colliders on ${listNames(colliders)} do not follow the avatar` : null,
        moving.length > 0 ? `the chains ${listNames(moving)} follow the avatar as they should` : 'no chain follows the avatar',
      ].filter(Boolean).join('; '),
    fix: () => 'wear it on an avatar with bones of those names (Decentraland\'s armature); in Babylon, add the avatar\'s container to the scene before registerWearable',
  },
  'unknown-item': {
    message: ({ call, itemId }) => `${call}: no wearable is registered as ${JSON.stringify(itemId)}, so nothing changed`,
    fix: ({ itemId }) => `registerWearable(scene, container, ${JSON.stringify(itemId)}, entry) first (and again after dispose), and pass that same id`,
  },
  'node-not-found': {
    message: ({ what, name, index }) => `${what} ${JSON.stringify(name)} (glTF node ${index}) has no object in the engine's scene, so it does not move`,
    fix: () => 'wear the scene loaded from the same GLB as the rig (or pass its nodes in glTF order)',
  },
  'collider-invalid': {
    message: ({ coreMessage }) => `setColliders: ${coreMessage}, so the hair passes through where that shape would be`,
    fix: () => 'give the shape a finite radius in [0, 1e6] (and offsets and tails within 1e6), or a plane a normal that is not [0, 0, 0]',
  },
  'collider-on-spring-bone': {
    message: ({ coreMessage }) => `setColliders: ${coreMessage}, so the hair passes through where that shape would be`,
    fix: () => 'put the collider on a bone of the avatar or an object that is no spring bone',
  },
  'body-collider-skipped': {
    message: ({ coreMessage }) => `setColliders: ${coreMessage}, so the hair passes through where those body shapes would be`,
    fix: () => 'wear the wearable on an avatar with Decentraland\'s armature (its Avatar_ bones), or pass avatarBones',
  },
  'collider-not-followed': {
    message: ({ names }) => `setColliders: no object of the scene is named ${listNames(names)}, so the colliders on it stay where the rest pose puts them and do not follow anything`,
    fix: () => 'pass the object itself as the collider\'s node (three.js: an Object3D; Babylon: a TransformNode), or the name of a node of the wearable, the avatar or the scene',
  },
});

/** The diagnostic of `code` with these facts. */
export function diagnostic(code, facts = {}, path = '') {
  const entry = kDiagnostics[code];
  if (!entry) throw new RangeError(`diagnostic: unknown code ${code}`);
  return Object.freeze({ code, message: entry.message(facts), fix: entry.fix(facts), path });
}

/** The diagnostic for a rig that never came: the module failed, or loadRig threw `error`. */
export function failureDiagnostic(error, moduleFailed) {
  return moduleFailed ? diagnostic('module-failed', { error }) : diagnostic('rig-failed', { error }, typeof error?.path === 'string' ? error.path : '');
}

/**
 * The entry's names that are bones of the GLB (nodes with children) and would start a chain but
 * do not: spring-bone names, no isRoot, not simulated, and no such name above them (a member below
 * one joins that chain once it has its root). `nodes`: glTF nodes ({ name, children }).
 */
function topUnrooted(entry, nodes, jointNames) {
  const byName = new Map();
  const parent = new Map();
  nodes.forEach((node, i) => {
    if (node && !byName.has(node.name)) byName.set(node.name, i);
    for (const child of node?.children ?? []) parent.set(child, i);
  });
  const unrooted = new Set();
  for (const name of Object.keys(entry)) {
    const i = byName.get(name);
    if (i === undefined || !isSpringBoneName(name) || jointNames.has(name) || entry[name]?.isRoot === true) continue;
    if ((nodes[i].children?.length ?? 0) > 0) unrooted.add(i);  // a bone, not a tip
  }
  const below = (i) => {
    for (let up = parent.get(i); up !== undefined; up = parent.get(up)) if (unrooted.has(up)) return true;
    return false;
  };
  return [...unrooted].filter((i) => !below(i)).map((i) => nodes[i].name);
}

/**
 * The reasons a loaded rig leaves hair at rest, in the order they are worth fixing; empty when
 * the hair moves as the metadata says.
 *
 * rig:          the springbones rig.
 * springBones:  what the caller passed as springBones (null or undefined: none).
 * entry:        the models entry the rig read (node name -> parameters); null when springBones
 *               has none for this GLB; undefined when the caller handed over a rig without it.
 * nodes:        the GLB's glTF nodes ({ name, children }), index = glTF node index.
 */
export function rigDiagnostics({ rig, springBones, entry, nodes }) {
  const fromCore = rig.warnings
    .filter((w) => w.code === 'models-missing' || w.code === 'model-not-found')
    .map((w) => diagnostic(w.code, { coreMessage: w.message }, w.path));
  if (fromCore.length > 0) return fromCore;
  const springNames = nodes.map((n) => n?.name).filter(isSpringBoneName);
  if (entry === undefined) {
    return rig.joints.length === 0 && springNames.length > 0 ? [diagnostic('no-chains', { springNames })] : [];
  }
  if (springBones === null || springBones === undefined) {
    return springNames.length > 0 ? [diagnostic('springbones-missing', { springNames })] : [];
  }
  if (entry === null) return [];  // the core said model-not-found or models-missing above
  const names = Object.keys(entry);
  const nodeNames = new Set(nodes.map((n) => n?.name));
  if (names.length > 0 && names.every((name) => !nodeNames.has(name))) return [diagnostic('entry-not-matched', { names })];
  const path = `/models${pointerToken(rig.contentHash)}`;
  const tops = topUnrooted(entry, nodes, new Set(rig.joints.map((j) => j.name)));
  if (rig.joints.length === 0) {
    const candidates = tops.length > 0 ? tops : names.filter((name) => isSpringBoneName(name) && nodeNames.has(name));
    return candidates.length > 0 ? [diagnostic('no-chain-root', { names: candidates }, path)] : [];
  }
  return tops.length > 0 ? [diagnostic('unrooted-bones', { names: tops }, path)] : [];
}

/**
 * bone-not-matched for the rig drivers `drivers` (indices into rig.drivers) that follow no bone
 * of the avatar, `bones` the names of the avatar bones that were missing; null when there is none.
 */
export function boneNotMatched(rig, drivers, bones) {
  if (drivers.size === 0 || rig.joints.length === 0) return null;
  const still = [];
  const moving = [];
  for (const root of rig.chains) {
    const joint = rig.joints[root];
    (drivers.has(joint.parentDriver) ? still : moving).push(joint.name);
  }
  const colliders = [...new Set(rig.colliders.filter((c) => drivers.has(c.driver)).map((c) => c.node))];
  return diagnostic('bone-not-matched', { bones, still, moving, colliders });
}

/**
 * A function that writes a diagnostic to the console once per code: `label()` names the wearable
 * (called when a line is written, when the rig may have arrived with its hash).
 */
export function consoleReporter(label) {
  const said = new Set();
  return (found) => {
    if (said.has(found.code)) return;
    said.add(found.code);
    console.warn(`springbones [${found.code}] ${label()}: ${found.message}. Fix: ${found.fix}.`);
  };
}
