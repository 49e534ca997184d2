// Why a worn wearable's spring bones do not move, said once. Each case here leaves the hair at
// rest with nothing else going wrong (no exception, the wearable is drawn), so without a word the
// user sees a static ponytail and no reason:
//
//   module-failed     the springbones module did not load (the rig never arrives);
//   rig-failed        loadRig refused the wearable's metadata or options (the rig never arrives);
//   models-missing    springBones has no `models` (the core's warning, surfaced);
//   model-not-found   springBones.models has no entry for this GLB's hash (the core's warning);
//   no-chain-root     the entry names the spring bones, but none with isRoot: true;
//   no-chains         the rig simulates nothing although the GLB has spring-bone nodes;
//   bone-not-matched  a bone the chains hang from has no bone of that name in the avatar, so the
//                     chains follow the avatar root instead of the head.
//
// Each becomes a warning ({ code, message, fix, path }) on the attachment (and on the loaded
// wearable) and one console.warn per wearable and code: a wearable worn by 100 avatars, or a frame
// loop, says it once. Not re-exported by index.js: the plugin and the adapter share it.

/** Symbol of the option with which SpringBonesWearable.wear() hands its context to attachWearable. */
export const kWearableContext = Symbol('springbones.wearableContext');

const kSpringBoneName = /springbone/i;

/**
 * A function that writes a warning to the console once per code. `label()` names the wearable
 * (it is called when a warning is written, when the rig may have arrived with its hash).
 */
export function consoleReporter(label) {
  const said = new Set();
  return (warning) => {
    if (said.has(warning.code)) return;
    said.add(warning.code);
    console.warn(`springbones [${warning.code}] ${label()}: ${warning.message}; the spring bones stay at rest. Fix: ${warning.fix}`);
  };
}

/** The warning for a rig that never arrived: the module or loadRig failed with `error`. */
export function failureWarning(error, stage = null) {
  const code = stage ?? (['module-load-failed', 'module-not-found'].includes(error?.code) ? 'module-failed' : 'rig-failed');
  const what = `${error?.name ?? 'Error'}${error?.code ? ` [${error.code}]` : ''}: ${error?.message ?? String(error)}`;
  // The texts are short on purpose: they ship in every preview (three.min.js).
  return code === 'module-failed'
    ? { code, path: '', message: `the springbones module did not load (${what})`, fix: 'serve the .wasm (README, "Finding the .wasm") or use springbones/inline.' }
    : { code, path: error?.path ?? '', message: `loadRig failed (${what})`, fix: 'correct what the error names (also on ready and .error).' };
}

/**
 * The rig-level reasons for no motion: the core's models-missing / model-not-found, else, when
 * the rig simulates nothing, an entry without isRoot (`entry`: the models entry used, when the
 * caller knows it) or a GLB whose spring-bone nodes `springNodeNames` no chain uses.
 */
export function rigWarnings(rig, { entry = null, springNodeNames = [] } = {}) {
  const out = [];
  for (const w of rig.warnings ?? []) {
    const fix = w.code === 'model-not-found' ? 'pass this GLB\'s models key: entity + bodyShape, contentHash or glb.'
      : w.code === 'models-missing' ? 'pass the wearable\'s data.springBones ({ version, models }).' : null;
    if (fix) out.push({ code: w.code, path: w.path, message: w.message, fix });
  }
  if (out.length > 0 || rig.joints.length > 0) return out;
  const entryNodes = entry !== null && typeof entry === 'object' ? Object.keys(entry).filter((name) => kSpringBoneName.test(name)) : [];
  if (entryNodes.length > 0) {
    out.push({
      code: 'no-chain-root', path: `/models/${rig.contentHash}`,
      message: `no spring bone of the models entry (${list(entryNodes)}) has isRoot: true`,
      fix: `set "isRoot": true on each chain's top spring bone (e.g. ${entryNodes[0]}).`,
    });
  } else if (springNodeNames.length > 0) {
    out.push({
      code: 'no-chains', path: '',
      message: `no chain, though the GLB has spring bones (${list(springNodeNames)})`,
      fix: 'pass springBones with an entry for this GLB\'s hash, isRoot: true on each chain\'s top spring bone.',
    });
  }
  return out;
}

/** The warning for drivers that no avatar bone matched (names: their glTF names). */
export function unmatchedWarning(names) {
  return {
    code: 'bone-not-matched', path: '',
    message: `the avatar has no bone named ${list(names)}, which the chains hang from`,
    fix: 'wear it on an avatar with bones of those names (Decentraland\'s armature).',
  };
}

/** The glTF names of the nodes of a glTF JSON that are spring-bone candidates (name contains "springbone"). */
export function springNodeNamesOf(nodes) {
  return (Array.isArray(nodes) ? nodes : []).map((n) => n?.name).filter((n) => typeof n === 'string' && kSpringBoneName.test(n));
}

const list = (names) => (names.length <= 3 ? names.join(', ') : `${names.slice(0, 3).join(', ')} and ${names.length - 3} more`);
