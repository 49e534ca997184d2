// What the creator panel does with a dropped metadata file before handing it to the JS API: tell a
// data.springBones object from a wearable entity, list an entity's body shapes, and build the
// entity that tools.validateSpringBones and tools.setSpringBoneParams need (they judge models keys
// against the representations' main-file hashes, so the panel hands them one that wears the GLB
// being edited). Plain functions over JSON: no DOM, no three.js, no WebAssembly.
//
// Everything about spring bones themselves (candidates, validation, Builder edits, hashes) is the
// API's (web/springbones.js); nothing here re-implements it.

const isObject = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);

export const BODY_SHAPES = Object.freeze([
  'urn:decentraland:off-chain:base-avatars:BaseMale',
  'urn:decentraland:off-chain:base-avatars:BaseFemale',
]);

/** What a dropped JSON file is: 'springBones' ({version, models}), 'entity' (catalyst entity or
 *  Builder item, with data), or 'unknown'. */
export function classifyJson(value) {
  if (!isObject(value)) return 'unknown';
  if ('models' in value || ('version' in value && Object.keys(value).length <= 2 && typeof value.version === 'number')) return 'springBones';
  if (isObject(value.metadata?.data) || isObject(value.data)) return 'entity';
  return 'unknown';
}

/** The data object of a catalyst entity ({metadata: {data}}) or a Builder item ({data}), or null. */
const dataOf = (entity) => (isObject(entity?.metadata?.data) ? entity.metadata.data : isObject(entity?.data) ? entity.data : null);

/** data.springBones of an entity or Builder item, or null. */
export function springBonesOf(entity) {
  const data = dataOf(entity);
  return data && 'springBones' in data ? data.springBones : null;
}

/** The entity's content list as a Map file -> hash (both the catalyst's and the Builder's form). */
function filesOf(entity) {
  const files = new Map();
  if (Array.isArray(entity?.content)) {
    for (const f of entity.content) if (typeof f?.file === 'string' && typeof f?.hash === 'string') files.set(f.file, f.hash);
  } else if (isObject(entity?.contents)) {
    for (const [file, hash] of Object.entries(entity.contents)) if (typeof hash === 'string') files.set(file, hash);
  }
  return files;
}

/** The representations: [{ bodyShapes: string[], mainFile, mainFileHash }] (null when unknown). */
export function representationsOf(entity) {
  const files = filesOf(entity);
  const reps = Array.isArray(dataOf(entity)?.representations) ? dataOf(entity).representations : [];
  return reps.map((r) => ({
    bodyShapes: Array.isArray(r?.bodyShapes) ? r.bodyShapes.filter((s) => typeof s === 'string') : [],
    mainFile: typeof r?.mainFile === 'string' ? r.mainFile : null,
    mainFileHash: typeof r?.mainFile === 'string' ? files.get(r.mainFile) ?? null : null,
  }));
}

/**
 * The entity the API calls get: `springBones` as its data.springBones, and the GLB being edited
 * (`file`, `hash`) as the main file of the representation worn by `bodyShape`. Without an entity,
 * a minimal one whose single representation, for both body shapes, is the GLB. The input is not
 * modified.
 */
export function entityWearing({ entity = null, bodyShape = null, file, hash, springBones }) {
  if (!entity) {
    return {
      content: [{ file, hash }],
      metadata: { data: { representations: [{ bodyShapes: [...BODY_SHAPES], mainFile: file, contents: [file] }], springBones } },
    };
  }
  const out = structuredClone(entity);
  const data = dataOf(out);
  data.springBones = springBones;
  const reps = Array.isArray(data.representations) ? data.representations : [];
  const worn = reps.find((r) => Array.isArray(r?.bodyShapes) && r.bodyShapes.includes(bodyShape)) ?? reps[0];
  if (!worn) {
    data.representations = [{ bodyShapes: [...BODY_SHAPES], mainFile: file, contents: [file] }];
  }
  // Point the worn representation's main file at the edited GLB's hash (the edit is a new upload).
  const mainFile = typeof worn?.mainFile === 'string' ? worn.mainFile : file;
  if (worn && worn.mainFile !== mainFile) worn.mainFile = mainFile;
  if (Array.isArray(out.content)) {
    const entry = out.content.find((f) => f?.file === mainFile);
    if (entry) entry.hash = hash;
    else out.content.push({ file: mainFile, hash });
  } else if (isObject(out.contents)) {
    out.contents[mainFile] = hash;
  } else {
    out.content = [{ file: mainFile, hash }];
  }
  return out;
}
