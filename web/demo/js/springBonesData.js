// The creator panel's metadata logic, as plain functions over JSON (no DOM, no three.js, no WASM),
// so Node tests can check them: spring-bone candidates of a glTF, inherited parameters, Builder-
// style prefill, the SpringBonesData schema and the catalyst's cross-checks, and the export with
// stale hashes dropped.
//
// The JS API (web/springbones.js) does not expose the core's validator and Builder edits yet
// (src/validation.h, src/builder_edits.h); until it does, this file is the page's minimum copy of
// them. Its accept/reject decisions are tested against tests/fixtures/validation_cases.json.

/** ADR-316 defaults (DESIGN.md section 4). */
export const DEFAULTS = Object.freeze({ stiffness: 2, gravityPower: 0, gravityDir: Object.freeze([0, -1, 0]), drag: 0.5 });
/** Inclusive ranges of the SpringBonesData schema (@dcl/schemas). */
export const RANGES = Object.freeze({
  stiffness: [0, 4], gravityPower: [0, 2], drag: [0, 1], gravityDir: [-10, 10],
});
/** The Builder's cap on configured spring bones (a warning there, not a deploy rule). */
export const BUILDER_MAX_BONES = 12;

/** ADR-316 discovery rule: the name contains "springbone", ASCII case-insensitive. (A regular
 *  expression with /i and no /u never folds a non-ASCII character onto an ASCII one.) */
export const isSpringBoneName = (name) => typeof name === 'string' && /springbone/i.test(name);

const isObject = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);
const isNumber = (v) => typeof v === 'number' && Number.isFinite(v);
const escapePointer = (key) => String(key).replace(/~/g, '~0').replace(/\//g, '~1');

/**
 * The spring-bone candidates of a glTF JSON document, parents first (depth-first from the scene
 * roots), each with the nearest candidate ancestor, plus the names of the other nodes (the
 * choices for `center`).
 * @returns {{ candidates: {index, name, parent, children: number[], depth}[], otherNodes: string[] }}
 *   `parent` and `children` index into `candidates`.
 */
export function springBoneTree(gltfJson) {
  const nodes = Array.isArray(gltfJson?.nodes) ? gltfJson.nodes : [];
  const parentOf = new Array(nodes.length).fill(-1);
  nodes.forEach((node, i) => {
    for (const c of Array.isArray(node?.children) ? node.children : []) {
      if (Number.isInteger(c) && c >= 0 && c < nodes.length && parentOf[c] === -1 && c !== i) parentOf[c] = i;
    }
  });
  const candidates = [];
  const otherNodes = [];
  const slotOf = new Map();
  const seen = new Set();
  const visit = (i, candidateParent, depth) => {
    if (seen.has(i)) return;  // cycles and shared children: the core rejects those files anyway
    seen.add(i);
    const name = nodes[i]?.name;
    let parent = candidateParent;
    if (isSpringBoneName(name)) {
      const slot = candidates.length;
      candidates.push({ index: i, name, parent: candidateParent, children: [], depth });
      if (candidateParent >= 0) candidates[candidateParent].children.push(slot);
      slotOf.set(i, slot);
      parent = slot;
      depth += 1;
    } else if (typeof name === 'string' && name !== '') {
      otherNodes.push(name);
    }
    for (const c of Array.isArray(nodes[i]?.children) ? nodes[i].children : []) {
      if (Number.isInteger(c) && parentOf[c] === i) visit(c, parent, depth);
    }
  };
  nodes.forEach((_, i) => { if (parentOf[i] === -1) visit(i, -1, 0); });
  return { candidates, otherNodes: [...new Set(otherNodes)] };
}

/** A complete entry (all four schema-required fields) from a possibly partial one. */
export function completeEntry(entry = {}) {
  const out = {
    stiffness: isNumber(entry.stiffness) ? entry.stiffness : DEFAULTS.stiffness,
    gravityPower: isNumber(entry.gravityPower) ? entry.gravityPower : DEFAULTS.gravityPower,
    gravityDir: Array.isArray(entry.gravityDir) && entry.gravityDir.length === 3 && entry.gravityDir.every(isNumber)
      ? [...entry.gravityDir] : [...DEFAULTS.gravityDir],
    drag: isNumber(entry.drag) ? entry.drag : DEFAULTS.drag,
  };
  if (entry.center !== undefined) out.center = entry.center;
  if (entry.isRoot !== undefined) out.isRoot = entry.isRoot;
  return out;
}

/**
 * The parameters a candidate runs with: its own entry, else the nearest candidate ancestor's, else
 * the defaults. Returns { params, from } where `from` is the name whose entry applies (or null).
 */
export function effectiveParams(tree, slot, entries) {
  for (let s = slot; s >= 0; s = tree.candidates[s].parent) {
    const name = tree.candidates[s].name;
    if (isObject(entries?.[name])) return { params: completeEntry(entries[name]), from: name };
  }
  return { params: completeEntry(), from: null };
}

/**
 * Builder-style prefill for a GLB with no parameters: every top-most candidate becomes a root with
 * the defaults (decentraland/builder getDefaultSpringBoneRoots, without its 12-bone cap: the cap
 * is reported as a warning instead).
 */
export function prefillEntries(tree) {
  const entries = {};
  for (const c of tree.candidates) {
    if (c.parent === -1) entries[c.name] = { ...completeEntry(), isRoot: true };
  }
  return entries;
}

// ---------------------------------------------------------------------------------------------
// Validation

/**
 * The SpringBonesData JSON schema of @dcl/schemas, with Ajv's wording: [{ path, message }], empty
 * when valid. `path` is a JSON pointer inside springBones.
 */
export function validateSchema(data) {
  const errors = [];
  const err = (path, message) => errors.push({ path, message });
  if (!isObject(data)) {
    err('', 'must be object');
    return errors;
  }
  for (const key of Object.keys(data)) {
    if (key !== 'version' && key !== 'models') err('', `must NOT have additional properties ('${key}')`);
  }
  if (!('version' in data)) err('', "must have required property 'version'");
  else if (!isNumber(data.version) || !Number.isInteger(data.version)) err('/version', 'must be integer');
  else if (data.version !== 1) err('/version', 'must be equal to one of the allowed values (1)');
  if (!('models' in data)) {
    err('', "must have required property 'models'");
    return errors;
  }
  if (!isObject(data.models)) {
    err('/models', 'must be object');
    return errors;
  }
  for (const [hash, bones] of Object.entries(data.models)) {
    const hashPath = `/models/${escapePointer(hash)}`;
    if (!isObject(bones)) {
      err(hashPath, 'must be object');
      continue;
    }
    for (const [bone, entry] of Object.entries(bones)) {
      const p = `${hashPath}/${escapePointer(bone)}`;
      if (!isObject(entry)) {
        err(p, 'must be object');
        continue;
      }
      for (const field of ['stiffness', 'gravityPower', 'gravityDir', 'drag']) {
        if (!(field in entry)) err(p, `must have required property '${field}'`);
      }
      for (const field of ['stiffness', 'gravityPower', 'drag']) {
        if (!(field in entry)) continue;
        const v = entry[field];
        const [lo, hi] = RANGES[field];
        if (!isNumber(v)) err(`${p}/${field}`, 'must be number');
        else if (v < lo) err(`${p}/${field}`, `must be >= ${lo}`);
        else if (v > hi) err(`${p}/${field}`, `must be <= ${hi}`);
      }
      if ('gravityDir' in entry) {
        const dir = entry.gravityDir;
        if (!Array.isArray(dir)) err(`${p}/gravityDir`, 'must be array');
        else {
          if (dir.length > 3) err(`${p}/gravityDir`, 'must NOT have more than 3 items');
          if (dir.length < 3) err(`${p}/gravityDir`, 'must NOT have fewer than 3 items');
          dir.slice(0, 3).forEach((v, k) => {
            if (!isNumber(v)) err(`${p}/gravityDir/${k}`, 'must be number');
            else if (v < RANGES.gravityDir[0]) err(`${p}/gravityDir/${k}`, `must be >= ${RANGES.gravityDir[0]}`);
            else if (v > RANGES.gravityDir[1]) err(`${p}/gravityDir/${k}`, `must be <= ${RANGES.gravityDir[1]}`);
          });
        }
      }
      if ('center' in entry && entry.center !== null && typeof entry.center !== 'string') err(`${p}/center`, 'must be string');
      if ('isRoot' in entry && entry.isRoot !== null && typeof entry.isRoot !== 'boolean') err(`${p}/isRoot`, 'must be boolean');
    }
  }
  return errors;
}

/**
 * What the catalyst checks at deploy time: the schema, then every models key must be the main-file
 * hash of a current representation (`activeHashes`) and every bone name must contain
 * "springbone". Returns [{ path, message }].
 */
export function validateForDeploy(data, activeHashes) {
  if (!data) return [];  // the catalyst skips any falsy springBones (absent, null, 0, "", false)
  const schemaErrors = validateSchema(data);
  if (schemaErrors.length) return schemaErrors;
  const errors = [];
  const active = new Set(activeHashes);
  for (const [hash, bones] of Object.entries(data.models)) {
    const hashPath = `/models/${escapePointer(hash)}`;
    if (!active.has(hash)) errors.push({ path: hashPath, message: `key ${hash} is not the content hash of any representation's main file` });
    for (const bone of Object.keys(bones)) {
      if (!isSpringBoneName(bone)) errors.push({ path: `${hashPath}/${escapePointer(bone)}`, message: `bone name '${bone}' does not contain "springbone"` });
    }
  }
  return errors;
}

/**
 * Editor warnings that are not deploy errors: entries naming no node of the GLB, a center that
 * names no node or a spring node, more configured bones than the Builder allows, no root at all.
 */
export function editorWarnings(tree, entries) {
  const warnings = [];
  const names = new Set(tree.candidates.map((c) => c.name));
  const others = new Set(tree.otherNodes);
  for (const [bone, entry] of Object.entries(entries)) {
    if (!names.has(bone)) warnings.push({ path: bone, message: `'${bone}' is not a spring-bone node of this GLB: the entry does nothing` });
    const center = entry?.center;
    if (typeof center === 'string' && center !== '') {
      if (names.has(center)) warnings.push({ path: bone, message: `center '${center}' is a spring bone: the runtime falls back to world space` });
      else if (!others.has(center)) warnings.push({ path: bone, message: `center '${center}' is not a node of this GLB: the runtime falls back to world space` });
    }
  }
  const configured = Object.keys(entries).filter((n) => names.has(n)).length;
  if (configured > BUILDER_MAX_BONES) {
    warnings.push({ path: '', message: `${configured} configured bones: the Builder allows at most ${BUILDER_MAX_BONES}` });
  }
  if (tree.candidates.length && !Object.values(entries).some((e) => e?.isRoot === true)) {
    warnings.push({ path: '', message: 'no entry has isRoot: true, so nothing is simulated' });
  }
  return warnings;
}

// ---------------------------------------------------------------------------------------------
// Entities and export

/** What a dropped JSON file is: 'springBones' ({version, models}), 'entity' (catalyst entity or
 *  Builder item, with representations), or 'unknown'. */
export function classifyJson(value) {
  if (!isObject(value)) return 'unknown';
  if ('models' in value || ('version' in value && Object.keys(value).length <= 2 && typeof value.version === 'number')) return 'springBones';
  if (isObject(value.metadata?.data) || isObject(value.data)) return 'entity';
  return 'unknown';
}

/** data.springBones of an entity ({metadata: {data}}) or Builder item ({data}), or null. */
export function springBonesOf(entity) {
  const data = isObject(entity?.metadata?.data) ? entity.metadata.data : entity?.data;
  return isObject(data) && 'springBones' in data ? data.springBones : null;
}

/** The representations of an entity with their main file's hash (null when not listed). */
export function representationsOf(entity) {
  const data = isObject(entity?.metadata?.data) ? entity.metadata.data : entity?.data;
  const files = new Map();
  if (Array.isArray(entity?.content)) {
    for (const f of entity.content) if (typeof f?.file === 'string' && typeof f?.hash === 'string') files.set(f.file, f.hash);
  } else if (isObject(entity?.contents)) {
    for (const [file, hash] of Object.entries(entity.contents)) if (typeof hash === 'string') files.set(file, hash);
  }
  const reps = Array.isArray(data?.representations) ? data.representations : [];
  return reps.map((r) => ({
    bodyShapes: Array.isArray(r?.bodyShapes) ? r.bodyShapes.filter((s) => typeof s === 'string') : [],
    mainFile: typeof r?.mainFile === 'string' ? r.mainFile : null,
    mainFileHash: typeof r?.mainFile === 'string' ? files.get(r.mainFile) ?? null : null,
  }));
}

const shapeMatches = (listed, wanted) => listed === wanted || listed.endsWith(`:${wanted}`) || wanted.endsWith(`:${listed}`);

/**
 * The hashes the exported models may keep: the edited GLB's hash, plus the main-file hashes of the
 * entity's representations that do not wear the edited GLB (the other body shape's model).
 */
export function activeHashes(glbHash, entity, bodyShape) {
  const hashes = [glbHash];
  if (entity) {
    for (const r of representationsOf(entity)) {
      const edited = bodyShape && r.bodyShapes.some((s) => shapeMatches(s, bodyShape));
      if (!edited && r.mainFileHash && !hashes.includes(r.mainFileHash)) hashes.push(r.mainFileHash);
    }
  }
  return hashes;
}

/**
 * data.springBones to publish: the edited entries under the GLB's hash, entries of other active
 * hashes kept from the loaded data, every other (stale) hash dropped. An empty entry map is left
 * out (the Builder does the same). Returns { data, dropped }.
 */
export function exportSpringBones({ glbHash, entries, original = null, active = [glbHash] }) {
  const models = {};
  if (Object.keys(entries).length) models[glbHash] = sortEntry(entries);
  const dropped = [];
  if (isObject(original?.models)) {
    for (const [hash, bones] of Object.entries(original.models)) {
      if (hash === glbHash) continue;
      if (active.includes(hash) && isObject(bones) && Object.keys(bones).length) models[hash] = bones;
      else dropped.push(hash);
    }
  }
  return { data: { version: 1, models }, dropped };
}

// Entries with their fields in the ADR's order, so exports read the same way every time.
function sortEntry(entries) {
  const order = ['stiffness', 'gravityPower', 'gravityDir', 'drag', 'center', 'isRoot'];
  const out = {};
  for (const [bone, entry] of Object.entries(entries)) {
    const e = {};
    for (const k of order) if (k in entry) e[k] = entry[k];
    for (const k of Object.keys(entry)) if (!(k in e)) e[k] = entry[k];
    out[bone] = e;
  }
  return out;
}
