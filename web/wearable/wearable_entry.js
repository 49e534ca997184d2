// The models entry of a springBones and the Builder's live edit of it, for both adapters: which
// entry a rig reads (for the diagnostics), and how an edited entry is merged over the previous
// one before the rig is rebuilt (live updates keep the motion: rig_life.js).

const isObject = (value) => value !== null && typeof value === 'object' && !Array.isArray(value);

/** springBones.models[key] of a springBones (an object or its JSON text), or null. */
export function modelsEntry(springBones, key) {
  let value = springBones;
  if (typeof value === 'string') {
    try {
      value = JSON.parse(value);
    } catch {
      return null;  // loadRig refused it already
    }
  }
  const models = isObject(value) ? value.models : null;
  return isObject(models) && key !== null && key !== undefined && isObject(models[key]) ? models[key] : null;
}

/** An entry (node name -> parameters) under `key`, as a whole springBones. */
export function entryAsSpringBones(key, entry) {
  return { version: 1, models: { [key]: entry } };
}

/**
 * The models entry `params` merged over `previous`, as Decentraland's live tuning merges: every
 * name of `params`, its fields over the previous entry's; a non-finite number keeps the previous
 * value (the core would otherwise put the default in its place). Names `params` leaves out go.
 */
export function mergeEntry(previous, params) {
  const merged = {};
  for (const [name, entry] of Object.entries(params)) {
    const before = isObject(previous?.[name]) ? previous[name] : null;
    if (!isObject(entry) || before === null) {
      merged[name] = entry;
      continue;
    }
    const out = { ...before };
    for (const [field, value] of Object.entries(entry)) {
      if (typeof value === 'number' && !Number.isFinite(value) && before[field] !== undefined) continue;
      out[field] = value;
    }
    merged[name] = out;
  }
  return merged;
}
