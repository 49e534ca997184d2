// The creator panel: open a wearable GLB with its metadata (a data.springBones JSON or a whole
// entity), list its spring-bone nodes, edit each entry with live feedback, see the deploy-time
// validation and export data.springBones keyed by the GLB's content hash.
//
// Every edit rebuilds the rig from the GLB bytes and the edited entries (a few hundred
// microseconds for a wearable) and hands it to the preview, which switches every avatar's
// attachment to it without touching the animation. The GLB itself is never modified.
import { Group } from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import * as SkeletonUtils from 'three/addons/utils/SkeletonUtils.js';
import { wearableNodes } from '../../three/springBonesThree.js';
import { diagnostic } from '../../wearable/diagnostics.js';
import { isSpringBoneName } from '../../wearable/spring_bone_name.js';
import { classifyJson, entityWearing, representationsOf, springBonesOf } from './entity.js';

const $ = (id) => document.getElementById(id);
const ASSETS = new URL('../assets/', import.meta.url);
const SAMPLE = { glb: 'hair_wearable.glb', json: 'hair_wearable.metadata.json' };

const isObject = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);

// data.springBones entry fields in the order ADR-316 lists them: JSON key order means nothing to a
// program, but creators read the export. Unknown fields follow.
const ADR_FIELD_ORDER = ['stiffness', 'gravityPower', 'gravityDir', 'drag', 'center', 'isRoot'];

function inAdrOrder(entry) {
  if (!isObject(entry)) return entry;
  const ordered = {};
  for (const field of ADR_FIELD_ORDER) if (field in entry) ordered[field] = entry[field];
  for (const [field, value] of Object.entries(entry)) if (!(field in ordered)) ordered[field] = value;
  return ordered;
}

const isGlb = (bytes) => bytes.length >= 4 && bytes[0] === 0x67 && bytes[1] === 0x6c && bytes[2] === 0x54 && bytes[3] === 0x46;
const round = (v) => Math.round(v * 1000) / 1000;
const isNumber = (v) => typeof v === 'number' && Number.isFinite(v);
/** The Builder's cap on configured spring bones (a warning there, not a deploy rule). */
const BUILDER_MAX_BONES = 12;
const clamp = (v, lo, hi) => Math.min(hi, Math.max(lo, v));
const shortHash = (h) => (h && h.length > 16 ? `${h.slice(0, 10)}…${h.slice(-6)}` : h);

/** A value as JavaScript writes it: NaN and Infinity by name, where JSON.stringify writes null. */
const jsText = (v) => (typeof v === 'number' ? String(v) : Array.isArray(v) ? `[${v.map(jsText).join(', ')}]` : JSON.stringify(v));
const hasNonFinite = (v) => (typeof v === 'number' && !Number.isFinite(v)) || (Array.isArray(v) && v.some(hasNonFinite));

/** Longest path shown whole; a longer one loses whole segments after its first (the title has it all). */
const kPathChars = 40;

/**
 * A JSON path (pointer) as a span that wraps only between segments (a <wbr> before each '/') and,
 * when long, drops whole segments after the first for one '…' segment, never cutting a name.
 */
function pathElement(path) {
  const segments = path.split('/').slice(1);
  let shown = segments;
  for (let drop = 1; shown.join('/').length + 1 > kPathChars && segments.length - drop >= 2; drop++) {
    shown = [segments[0], '…', ...segments.slice(1 + drop)];
  }
  const span = element('span', { class: 'path', title: path });
  for (const segment of shown) span.append(document.createElement('wbr'), `/${segment}`);
  return span;
}

function element(tag, props = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(props)) {
    if (k === 'class') e.className = v;
    else if (k === 'dataset') Object.assign(e.dataset, v);
    else if (k in e) e[k] = v;
    else e.setAttribute(k, v);
  }
  for (const c of children) if (c !== null && c !== undefined) e.append(c);  // text via append: never parsed as HTML
  return e;
}

/** A glTF without scenes (valid: the ADR's example has none) gets one holding its root nodes. */
async function addDefaultScene(gltf) {
  const objects = await gltf.parser.getDependencies('node');
  const json = gltf.parser.json.nodes ?? [];
  const children = new Set(json.flatMap((n) => (Array.isArray(n.children) ? n.children : [])));
  const scene = new Group();
  scene.name = 'Scene';
  objects.forEach((o, i) => { if (!children.has(i) && !o.parent) scene.add(o); });
  gltf.scene = scene;
  gltf.scenes = [scene];
}

export class Creator {
  constructor(preview) {
    this.preview = preview;
    this.sb = preview.sb;
    this.tools = null;      // sb.creatorTools() (validation, Builder edits): loaded with the first GLB
    this.loader = new GLTFLoader();
    this.bytes = null;      // the GLB being edited
    this.name = '';
    this.hash = null;       // its content hash (the models key)
    this.tree = null;       // { candidates (tools.detectSpringBones, with children), otherNodes }
    this.entries = {};      // the edited models[hash]
    this.original = null;   // the springBones value that was loaded (other hashes survive export)
    this.entity = null;     // the entity, when one was loaded
    this.bodyShape = null;
    this.selected = -1;     // candidate slot shown in the editor
    this.messages = [];     // { level: 'error'|'warning'|'info', text }
    this.inputNote = null;  // { field, text }: the last number typed was outside its control's range
    this.exportUrl = null;
    this.busy = Promise.resolve();
    this.wire();
  }

  // ---- reading files

  wire() {
    $('file-glb').addEventListener('change', (e) => { this.openFiles(e.target.files); e.target.value = ''; });
    $('file-json').addEventListener('change', (e) => { this.openFiles(e.target.files); e.target.value = ''; });
    $('load-sample').addEventListener('click', () => this.queue(() => this.loadSample()));
    const zone = $('dropzone');
    const over = (on) => (e) => { e.preventDefault(); document.body.classList.toggle('dragging', on); };
    window.addEventListener('dragover', over(true));
    window.addEventListener('dragleave', (e) => { if (!e.relatedTarget) document.body.classList.remove('dragging'); });
    window.addEventListener('drop', (e) => {
      over(false)(e);
      if (e.dataTransfer?.files?.length) this.openFiles(e.dataTransfer.files);
    });
    zone.addEventListener('keydown', (e) => { if (e.key === 'Enter') $('file-glb').click(); });
    $('body-shape').addEventListener('change', (e) => { this.bodyShape = e.target.value; this.refreshEntityNotes(); this.refreshValidation(); });
    const rowOf = (e) => e.target.closest?.('#tree .node');
    $('tree').addEventListener('click', (e) => { const row = rowOf(e); if (row) this.select(Number(row.dataset.slot)); });
    $('tree').addEventListener('keydown', (e) => {
      const row = rowOf(e);
      if (row && (e.key === 'Enter' || e.key === ' ')) { e.preventDefault(); this.select(Number(row.dataset.slot)); }
    });
    this.wireEditor();
    $('export').addEventListener('click', () => this.showExport());
    $('copy-export').addEventListener('click', () => this.copyExport());
  }

  /** Loads run one after another (a second drop waits for the first). */
  queue(task) {
    this.busy = this.busy.then(task, task).catch((e) => this.fail(`Unexpected error: ${e.message}`));
    return this.busy;
  }

  openFiles(fileList) {
    const files = [...fileList];
    return this.queue(async () => {
      let glb = null;
      let json = null;
      for (const file of files) {
        const bytes = new Uint8Array(await file.arrayBuffer());
        if (/\.(glb|gltf)$/i.test(file.name) || isGlb(bytes)) glb = { name: file.name, bytes };
        else json = { name: file.name, bytes };
      }
      await this.open({ glb, json });
    });
  }

  async loadSample() {
    const [glbBytes, jsonBytes] = await Promise.all([SAMPLE.glb, SAMPLE.json].map(async (f) => {
      const r = await fetch(new URL(f, ASSETS));
      if (!r.ok) throw new Error(`${f}: HTTP ${r.status}`);
      return new Uint8Array(await r.arrayBuffer());
    }));
    await this.open({ glb: { name: SAMPLE.glb, bytes: glbBytes }, json: { name: SAMPLE.json, bytes: jsonBytes } });
  }

  /**
   * Opens a GLB and/or a JSON file. A GLB alone starts without parameters (prefilled defaults); a
   * JSON alone applies to the GLB already open. Anything that fails leaves the current state.
   */
  async open({ glb, json }) {
    const messages = [];
    let value = null;
    let kind = null;
    if (json) {
      try {
        value = JSON.parse(new TextDecoder('utf-8', { fatal: false }).decode(json.bytes));
      } catch (e) {
        return this.fail(`${json.name}: not valid JSON (${e.message})`);
      }
      kind = classifyJson(value);
      if (kind === 'unknown') return this.fail(`${json.name}: neither a data.springBones object ({version, models}) nor a wearable entity`);
    }
    if (!glb && !this.bytes) return this.fail('Open a GLB first (or together with the JSON).');

    let loaded = null;
    if (glb) {
      try {
        loaded = await this.readGlb(glb);
      } catch (e) {
        const code = e.code ? ` [${e.code}]` : '';
        return this.fail(`Could not load ${glb.name}${code}: ${e.message}`);
      }
    }

    // Commit: from here on nothing throws on bad input.
    if (loaded) {
      Object.assign(this, loaded);
      this.original = null;
      this.entity = null;
    }
    if (kind === 'springBones') {
      this.original = value;
      this.entity = null;
    } else if (kind === 'entity') {
      this.entity = value;
      this.original = springBonesOf(value);
    }
    this.setupBodyShapes();
    // What a catalyst would say about the file as loaded (the panel then shows the edited state).
    const loadedErrors = this.original ? this.validate(this.original) : [];
    const shown = (text) => text.split(this.hash).join('<GLB hash>');
    for (const e of loadedErrors.slice(0, 8)) messages.push({ level: 'warning', text: `loaded: ${shown(e.message)}` });
    if (loadedErrors.length > 8) messages.push({ level: 'warning', text: `… and ${loadedErrors.length - 8} more errors in the loaded springBones` });
    const picked = this.pickEntries();
    this.entries = picked.entries;
    if (picked.note) messages.push({ level: picked.level ?? 'info', text: picked.note });
    // JSON has no NaN or Infinity: a number too large for a double (1e999) parses as Infinity,
    // and would be written back as null. Named here, not shown as "null".
    for (const [node, entry] of Object.entries(this.entries)) {
      if (!isObject(entry)) continue;
      for (const [field, v] of Object.entries(entry)) {
        if (hasNonFinite(v)) {
          messages.push({ level: 'warning', text: `${node}: ${field} is ${jsText(v)} as read, not a finite number (JSON would write it as null); the runtime uses the default.` });
        }
      }
    }
    this.messages = messages;
    this.selected = this.tree.candidates.findIndex((c) => this.entries[c.name]?.isRoot === true);
    if (this.selected < 0 && this.tree.candidates.length) this.selected = 0;

    let rig;
    try {
      rig = this.buildRig();
    } catch (e) {
      // Cannot happen for entries we built; report rather than keep a half-open state.
      this.fail(`Could not build the rig: ${e.message}`);
      return;
    }
    if (loaded) this.preview.setWearable(loaded.gltf, rig, this.name);
    else this.preview.setRig(rig);
    if (this.tree.candidates.length === 0) this.messages.push({ level: 'warning', text: 'This GLB has no node whose name contains "springbone".' });
    this.refreshAll();
  }

  /** Checks the bytes with the core (hierarchy, limits) and three.js (meshes), hashes them. */
  async readGlb({ name, bytes }) {
    const hash = this.sb.contentHash(bytes);
    // A dropped file is bytes: the readers module reads them (the preview never needed it).
    await this.sb.readers();
    const probe = this.sb.loadRig(bytes, null, { contentHash: hash });  // throws SpringBonesError
    probe.dispose();
    // The creator tools are a second module that the preview never needed: downloaded now.
    this.tools ??= await this.sb.creatorTools();
    const copy = bytes.slice().buffer;  // GLTFLoader may keep views on it
    const gltf = await this.loader.parseAsync(copy, ASSETS.href);
    if (!gltf.scene) await addDefaultScene(gltf);
    wearableNodes(gltf, SkeletonUtils.clone(gltf.scene));  // what the preview will do: fail here, not there
    return { bytes, name, hash, gltf, tree: this.springBoneTree(bytes, hash, gltf.parser.json) };
  }

  /**
   * The GLB's spring-bone candidates (tools.detectSpringBones: parents first, defaults as params,
   * top-most ones marked isRoot as the Builder prefills them), each with its children's slots,
   * and the names of the other nodes (the choices for `center`).
   */
  springBoneTree(bytes, hash, gltfJson) {
    const candidates = this.tools.detectSpringBones(bytes, null, { contentHash: hash }).map((c) => ({ ...c, children: [] }));
    candidates.forEach((c, slot) => { if (c.parent >= 0) candidates[c.parent].children.push(slot); });
    const spring = new Set(candidates.map((c) => c.node));
    const nodes = Array.isArray(gltfJson?.nodes) ? gltfJson.nodes : [];
    const otherNodes = [...new Set(nodes.filter((n, i) => !spring.has(i) && typeof n?.name === 'string' && n.name !== '').map((n) => n.name))];
    return { candidates, otherNodes };
  }

  pickEntries() {
    const models = isObject(this.original?.models) ? this.original.models : {};
    const keys = Object.keys(models).filter((k) => isObject(models[k]));
    if (isObject(models[this.hash])) return { entries: structuredClone(models[this.hash]) };
    const entityKey = this.entityMainFileHash();
    if (entityKey && isObject(models[entityKey])) {
      return {
        entries: structuredClone(models[entityKey]),
        level: 'warning',
        note: `Using the entity's entry models["${shortHash(entityKey)}"] (its main-file hash); the export writes it under this GLB's hash ${shortHash(this.hash)}.`,
      };
    }
    if (keys.length === 1) {
      return {
        entries: structuredClone(models[keys[0]]),
        level: 'warning',
        note: `The metadata has no entry for this GLB's hash ${shortHash(this.hash)}; using its only entry, models["${keys[0]}"], which the export re-keys.`,
      };
    }
    const note = keys.length
      ? `None of the metadata's ${keys.length} entries is for this GLB's hash; top-most spring bones prefilled with the defaults as roots.`
      : 'No parameters for this GLB yet: top-most spring bones prefilled with the defaults as roots.';
    // The Builder's prefill: every top-most candidate a root with the defaults.
    const entries = {};
    for (const c of this.tree.candidates) if (c.isRoot) entries[c.name] = { ...structuredClone(c.params), isRoot: true };
    return { entries, note };
  }

  buildRig() {
    const metadata = { version: 1, models: { [this.hash]: this.entries } };
    return this.sb.loadRig(this.bytes, metadata, { contentHash: this.hash, ...this.preview.rigOptions() });
  }

  /** Rebuilds the rig with the same entries (the preview's colliders changed). */
  rebuild() {
    if (this.bytes) this.apply();
  }

  fail(text) {
    this.messages = [{ level: 'error', text }, ...this.messages.filter((m) => m.level !== 'error')];
    this.renderMessages();
    console.warn(`springbones demo: ${text}`);  // a user error, not a page error
  }

  // ---- entity

  setupBodyShapes() {
    const select = $('body-shape');
    select.replaceChildren();
    const reps = this.entity ? representationsOf(this.entity) : [];
    const shapes = [...new Set(reps.flatMap((r) => r.bodyShapes))];
    $('body-shape-row').hidden = shapes.length === 0;
    if (!shapes.length) {
      this.bodyShape = null;
      return;
    }
    for (const s of shapes) select.append(element('option', { value: s }, s.split(':').pop()));
    const wearing = reps.find((r) => r.mainFileHash === this.hash);
    this.bodyShape = wearing?.bodyShapes[0] ?? shapes[0];
    select.value = this.bodyShape;
  }

  entityMainFileHash() {
    if (!this.entity || !this.bodyShape) return null;
    const rep = representationsOf(this.entity).find((r) => r.bodyShapes.includes(this.bodyShape));
    return rep?.mainFileHash ?? null;
  }

  refreshEntityNotes() {
    this.messages = this.messages.filter((m) => !m.entityNote);
    const key = this.entityMainFileHash();
    if (this.entity && key && key !== this.hash) {
      this.messages.push({
        level: 'warning', entityNote: true,
        text: `The entity's main file for ${this.bodyShape.split(':').pop()} has hash ${shortHash(key)}, this GLB ${shortHash(this.hash)}: the export keys the parameters by the GLB's hash (update the entity's content list too).`,
      });
    }
    this.renderMessages();
  }

  /** The entity the API judges: the loaded one (or a minimal one) wearing this GLB. */
  entityFor(springBones) {
    return entityWearing({ entity: this.entity, bodyShape: this.bodyShape, file: this.name, hash: this.hash, springBones });
  }

  /** tools.validateSpringBones on `springBones` as part of entityFor: [{path, message}]. */
  validate(springBones) {
    try {
      return this.tools.validateSpringBones(this.entityFor(springBones));
    } catch (e) {
      return [{ path: e.path ?? '', message: e.message }];
    }
  }

  // ---- rendering

  refreshAll() {
    $('wearable-info').textContent = `${this.name} · ${this.bytes.length.toLocaleString('en')} bytes · hash ${this.hash}`;
    this.refreshEntityNotes();
    this.renderTree();
    this.renderEditor();
    this.refreshValidation();
    this.hideExport();
  }

  renderMessages() {
    $('messages').replaceChildren(...this.messages.map((m) => element('li', { class: m.level }, m.text)));
  }

  /** Builds the tree's rows once per GLB; decorateTree() keeps them current after edits. */
  renderTree() {
    const { candidates } = this.tree;
    const build = (slot) => {
      const c = candidates[slot];
      const row = element('div', {
        class: 'node', role: 'treeitem', tabIndex: 0, dataset: { node: c.name, slot: String(slot) },
      }, element('span', { class: 'dot' }), element('span', {}, c.name),
      element('span', { class: 'badge root', hidden: true }, 'root'),
      element('span', { class: 'badge override', hidden: true }, 'override'),
      c.children.length === 0 ? element('span', { class: 'badge' }, 'tip') : null);
      const li = element('li', {}, row);
      if (c.children.length) li.append(element('ul', { role: 'group' }, ...c.children.map(build)));
      return li;
    };
    const roots = candidates.map((c, slot) => (c.parent === -1 ? slot : -1)).filter((s) => s >= 0);
    $('tree').replaceChildren(...roots.map(build));
    this.decorateTree();
  }

  /**
   * Badges, simulated dots and the selection, updated in place (nothing in a row is replaced): an
   * edit committed by leaving a number box (its change event fires on the mousedown of the next
   * click) must not remove the element that click is landing on, or the click is lost.
   */
  decorateTree() {
    const { candidates } = this.tree;
    const simulated = new Set(this.preview.wearable?.rig.joints.map((j) => j.name));
    for (const row of $('tree').querySelectorAll('.node')) {
      const slot = Number(row.dataset.slot);
      const c = candidates[slot];
      const entry = isObject(this.entries[c.name]) ? this.entries[c.name] : null;
      row.querySelector('.badge.root').hidden = entry?.isRoot !== true;
      row.querySelector('.badge.override').hidden = !entry || entry.isRoot === true;
      const sim = simulated.has(c.name);
      const dot = row.querySelector('.dot');
      dot.className = `dot${sim ? ' sim' : ''}`;
      dot.textContent = sim ? '●' : '○';
      row.title = sim ? 'simulated joint' : 'not simulated';
      row.classList.toggle('selected', slot === this.selected);
    }
  }

  select(slot) {
    this.selected = slot;
    this.inputNote = null;
    for (const row of $('tree').querySelectorAll('.node')) row.classList.toggle('selected', Number(row.dataset.slot) === slot);
    this.renderEditor();
  }

  // ---- the parameter editor

  wireEditor() {
    const pairs = [
      ['stiffness', 'stiffness'], ['gravityPower', 'gravityPower'], ['drag', 'drag'],
      ['gx', 0], ['gy', 1], ['gz', 2],
    ];
    for (const [id, field] of pairs) {
      const slider = $(`param-${id}`);
      const box = $(`param-${id}-num`);
      const set = (v) => (typeof field === 'number' ? this.setDir(field, v) : this.setField(field, v));
      const noteField = typeof field === 'number' ? 'gravityDir' : field;
      slider.addEventListener('input', () => {
        this.inputNote = null;
        set(Number(slider.value));
      });
      box.addEventListener('change', () => {
        const v = Number(String(box.value).replace(',', '.'));
        if (box.value === '' || !Number.isFinite(v)) return this.renderEditor();  // revert
        const clamped = clamp(v, Number(box.min), Number(box.max));
        // Said on the control: the number typed is not the number kept.
        this.inputNote = clamped === v ? null
          : { field: noteField, text: `${v} is outside [${box.min}, ${box.max}]: set to ${clamped}.` };
        set(clamped);
      });
    }
    $('param-override').addEventListener('change', (e) => {
      const name = this.selectedName();
      if (!name) return;
      if (e.target.checked) this.ensureEntry();
      else delete this.entries[name];
      this.apply();
    });
    $('param-isRoot').addEventListener('change', (e) => {
      this.ensureEntry().isRoot = e.target.checked;
      this.apply();
    });
    $('param-center').addEventListener('change', (e) => {
      const entry = this.ensureEntry();
      if (e.target.value === '') delete entry.center;
      else entry.center = e.target.value;
      this.apply();
    });
  }

  selectedName() {
    return this.tree?.candidates[this.selected]?.name ?? null;
  }

  /**
   * The parameters the selected node runs with, as the core read them: its rig joint's (own entry,
   * else inherited; clamped, gravityDir normalised), else the defaults tools.detectSpringBones gave
   * (a tip, or a node in no chain).
   */
  runtimeParams(slot) {
    const c = this.tree.candidates[slot];
    const joint = this.preview.wearable?.rig.joints.find((j) => j.name === c.name);
    const p = joint ? joint.params : c.params;
    return { stiffness: p.stiffness, gravityPower: p.gravityPower, gravityDir: [...p.gravityDir], drag: p.drag };
  }

  /** Name of the nearest node at or above `slot` that has an entry, or null. */
  entryFrom(slot) {
    for (let s = slot; s >= 0; s = this.tree.candidates[s].parent) {
      if (isObject(this.entries[this.tree.candidates[s].name])) return this.tree.candidates[s].name;
    }
    return null;
  }

  /** What the editor shows: the entry's own finite values over what the node runs with. */
  shownParams(slot) {
    const params = this.runtimeParams(slot);
    const entry = this.entries[this.tree.candidates[slot].name];
    if (isObject(entry)) {
      for (const k of ['stiffness', 'gravityPower', 'drag']) if (isNumber(entry[k])) params[k] = entry[k];
      if (Array.isArray(entry.gravityDir) && entry.gravityDir.length === 3 && entry.gravityDir.every(isNumber)) params.gravityDir = [...entry.gravityDir];
    }
    return params;
  }

  /** The selected node's own entry, created from the values it currently runs with if needed;
   *  the schema's four required fields are always present. */
  ensureEntry() {
    const name = this.selectedName();
    const params = this.shownParams(this.selected);
    const entry = isObject(this.entries[name]) ? this.entries[name] : { isRoot: false };
    this.entries[name] = { ...entry, ...params };
    return this.entries[name];
  }

  setField(field, value) {
    if (!this.selectedName()) return;
    const box = $(`param-${field}-num`);
    this.ensureEntry()[field] = round(clamp(value, Number(box.min), Number(box.max)));
    this.apply();
  }

  setDir(k, value) {
    if (!this.selectedName()) return;
    const entry = this.ensureEntry();
    const box = $(`param-${['gx', 'gy', 'gz'][k]}-num`);
    entry.gravityDir = [...entry.gravityDir];
    entry.gravityDir[k] = round(clamp(value, Number(box.min), Number(box.max)));
    this.apply();
  }

  /** Rebuilds the rig from the edited entries; the animation keeps going. */
  apply() {
    try {
      this.preview.setRig(this.buildRig());
    } catch (e) {
      this.fail(`Could not rebuild the rig: ${e.message}`);
    }
    this.decorateTree();
    this.renderEditor();
    this.refreshValidation();
    this.hideExport();
  }

  renderEditor() {
    const name = this.selectedName();
    $('editor').hidden = !name;
    if (!name) return;
    const entry = isObject(this.entries[name]) ? this.entries[name] : null;
    const params = this.shownParams(this.selected);
    const from = this.entryFrom(this.selected);
    $('editor-title').textContent = name;
    $('editor-source').textContent = entry
      ? (entry.isRoot === true ? 'Chain root: its entry applies to the chain below it.' : this.memberText(name))
      : (from ? `No entry: inherits from ${from}. Moving a control creates an override.` : 'No entry: not part of a chain. Tick isRoot to start one.');
    $('param-override').checked = Boolean(entry);
    $('param-isRoot').checked = entry?.isRoot === true;
    const show = (id, v) => {
      $(`param-${id}`).value = String(v);
      $(`param-${id}-num`).value = String(round(v));
    };
    show('stiffness', params.stiffness);
    show('gravityPower', params.gravityPower);
    show('drag', params.drag);
    params.gravityDir.forEach((v, k) => show(['gx', 'gy', 'gz'][k], v));
    this.renderNotes(name);
    const center = $('param-center');
    const current = entry && typeof entry.center === 'string' ? entry.center : '';
    const options = [element('option', { value: '' }, entry?.isRoot === true ? 'none (world space)' : 'none (inherit / world space)')];
    for (const n of this.tree.otherNodes) options.push(element('option', { value: n }, n));
    if (current && !this.tree.otherNodes.includes(current)) options.push(element('option', { value: current }, `${current} (not a non-spring node)`));
    center.replaceChildren(...options);
    center.value = current;
  }

  /**
   * What an entry without isRoot is: a member of the chain a rooted ancestor starts, or, with no
   * such ancestor, a bone that stays at rest (the adapters' unrooted-bones diagnostic, word for word).
   */
  memberText(name) {
    for (let s = this.tree.candidates[this.selected].parent; s >= 0; s = this.tree.candidates[s].parent) {
      if (this.entries[this.tree.candidates[s].name]?.isRoot === true) return 'Member with its own entry (overrides what it inherits).';
    }
    const found = diagnostic('unrooted-bones', { names: [name] });
    return `${found.message}. Fix: ${found.fix}.`;
  }

  /**
   * Under each control, what became of its value: the runtime clamped it or replaced it (the rig's
   * warning on the entry the node runs with: its own, or the ancestor's it inherits), or the
   * number typed was outside the control's range.
   */
  renderNotes(name) {
    const from = this.entryFrom(this.selected);
    const rigWarnings = this.preview.wearable?.rig.warnings ?? [];
    const pointer = (node, field) => ['', 'models', this.hash, node, field].map((k) => k.replaceAll('~', '~0').replaceAll('/', '~1')).join('/');
    const controls = { stiffness: ['stiffness'], gravityPower: ['gravityPower'], drag: ['drag'], gravityDir: ['gx', 'gy', 'gz'] };
    for (const [field, ids] of Object.entries(controls)) {
      const notes = [];
      if (from) {
        const at = pointer(from, field);
        for (const w of rigWarnings) {
          if (w.path === at || w.path.startsWith(`${at}/`)) {
            notes.push(`${from === name ? '' : `inherited from ${from}: `}${this.nameNonFinite(w.message, w.path)}`);
          }
        }
      }
      if (this.inputNote?.field === field) notes.push(this.inputNote.text);
      const note = $(`param-${field}-note`);
      note.textContent = notes.join(' ');
      note.hidden = notes.length === 0;
      for (const id of ids) $(`param-${id}-num`).classList.toggle('clamped', notes.length > 0);
    }
  }

  // ---- validation and export

  /**
   * data.springBones to publish, through the Builder edit of the API (tools.setSpringBoneParams): the
   * edited entries under this GLB's hash, the other representations' entries kept, every models
   * key no representation uses (stale) dropped. Returns { data, dropped }.
   */
  exportResult() {
    const models = isObject(this.original?.models) ? { ...this.original.models } : {};
    delete models[this.hash];
    models[this.hash] = this.entries;
    const draft = { version: 1, models };
    // Re-setting one entry (or removing a node that has none) makes the API drop the stale keys.
    const name = Object.keys(this.entries).find(isSpringBoneName) ?? 'springbone';
    let data;
    try {
      data = this.tools.setSpringBoneParams(draft, this.entityFor(draft), this.bodyShape ?? 'BaseMale', name, this.entries[name] ?? null);
    } catch (e) {
      this.fail(`Export: ${e.message}`);
      data = draft;
    }
    if (isObject(data.models?.[this.hash]) && Object.keys(data.models[this.hash]).length === 0) delete data.models[this.hash];  // as the Builder
    const dropped = Object.keys(isObject(this.original?.models) ? this.original.models : {}).filter((h) => !(h in data.models));
    return { data: { version: data.version, models: data.models }, dropped };
  }

  /** The export as people read it: each entry's fields in the ADR's order (the API sorts them). */
  exportText(data = this.exportResult().data) {
    const models = {};
    for (const [hash, bones] of Object.entries(data.models)) {
      models[hash] = isObject(bones) ? Object.fromEntries(Object.entries(bones).map(([name, e]) => [name, inAdrOrder(e)])) : bones;
    }
    return JSON.stringify({ version: data.version, models }, null, 2);
  }

  refreshValidation() {
    const { data } = this.exportResult();
    const errors = this.validate(data);
    // The core's runtime warnings (clamps, missing nodes and centers, nested roots...), then the
    // Builder's two that are no rule of the core: its bone cap, and nothing marked as a root.
    const warnings = (this.preview.wearable?.rig.warnings ?? []).map((w) => ({ text: this.nameNonFinite(w.message, w.path), path: w.path, code: w.code }));
    const names = new Set(this.tree.candidates.map((c) => c.name));
    const configured = Object.keys(this.entries).filter((n) => names.has(n)).length;
    if (configured > BUILDER_MAX_BONES) warnings.push({ text: `${configured} configured bones: the Builder allows at most ${BUILDER_MAX_BONES}`, path: '' });
    if (names.size && !Object.values(this.entries).some((e) => e?.isRoot === true)) warnings.push({ text: 'no entry has isRoot: true, so nothing is simulated', path: '' });
    const shown = (path) => path.split(this.hash).join('<GLB hash>');  // the hash is 59 characters
    const items = [];
    for (const e of errors) {
      // The catalyst's message starts with the path ("springBones/models/<hash>/node/field must
      // be ..."): the path is shown as a path, then the rest.
      const text = this.nameNonFinite(e.message, e.path);
      const prefix = `springBones${e.path}`;
      items.push(e.path && text.startsWith(prefix)
        ? element('li', { class: 'error' }, pathElement(shown(e.path)), text.slice(prefix.length))
        : element('li', { class: 'error' }, shown(text)));
    }
    for (const w of warnings) {
      items.push(element('li', { class: 'warning' }, shown(w.text), w.path ? ' ' : '', w.path ? pathElement(shown(w.path)) : null));
    }
    // Green only for spring bones that pass and move: a GLB without any, or a rig that simulates
    // nothing, has nothing a pass could vouch for.
    const simulated = this.preview.wearable?.rig.joints.length ?? 0;
    let passed = false;
    if (!errors.length) {
      if (this.tree.candidates.length === 0) {
        items.unshift(element('li', { class: 'warning empty' }, 'No spring bones in this GLB (no node name contains "springbone"): nothing to check or simulate.'));
      } else if (simulated === 0) {
        items.unshift(element('li', { class: 'warning empty' }, 'Passes the catalyst checks, but nothing is simulated (see the warnings).'));
      } else {
        passed = true;
        items.unshift(element('li', { class: 'ok' }, 'Passes the catalyst checks (SpringBonesData schema, models keys, bone names).'));
      }
    }
    $('validation').replaceChildren(...items);
    this.lastValidation = { errors, warnings, passed };
  }

  messageList() {
    return this.messages.map((m) => ({ level: m.level, text: m.text }));
  }

  validationList() {
    return structuredClone(this.lastValidation ?? { errors: [], warnings: [], passed: false });
  }

  /** The value at a JSON pointer into { models: { [this GLB's hash]: the edited entries } }. */
  valueAt(path) {
    let value = { models: { [this.hash]: this.entries } };
    for (const raw of path.split('/').slice(1)) {
      const key = raw.replaceAll('~1', '/').replaceAll('~0', '~');
      if (value === null || typeof value !== 'object' || !Object.hasOwn(value, key)) return undefined;
      value = value[key];
    }
    return value;
  }

  /**
   * A message of the core or the catalyst about the value at `path`, with a NaN or Infinity named:
   * the catalyst saw it as JSON, where it is null ("stiffness must be number"); the runtime, which
   * takes the object as it is, says it is not finite.
   */
  nameNonFinite(text, path) {
    if (!path) return text;
    const value = this.valueAt(path);
    if (!hasNonFinite(value)) return text;
    if (/ is not finite;/.test(text)) return text.replace(' is not finite;', ` is ${jsText(value)}, not a finite number;`);
    const json = JSON.stringify(value);
    let named = text.includes(json) ? text.split(json).join(jsText(value)) : text;
    named = named.replace('not a number', 'not a finite number');
    return named === text ? `${text} (it is ${jsText(value)}, which JSON writes as null)` : named;
  }

  showExport() {
    const { data, dropped } = this.exportResult();
    const text = this.exportText(data);
    const area = $('export-json');
    area.hidden = false;
    area.value = text;
    if (this.exportUrl) URL.revokeObjectURL(this.exportUrl);
    this.exportUrl = URL.createObjectURL(new Blob([text + '\n'], { type: 'application/json' }));
    const link = $('download-export');
    link.href = this.exportUrl;
    link.hidden = false;
    $('copy-export').disabled = false;
    const notes = [`data.springBones keyed by ${this.hash}.`];
    if (dropped.length) notes.push(`Dropped ${dropped.length} stale entr${dropped.length === 1 ? 'y' : 'ies'}: ${dropped.map(shortHash).join(', ')}.`);
    const errors = this.lastValidation?.errors.length ?? 0;
    if (errors) notes.push(`${errors} validation error${errors === 1 ? '' : 's'}: the catalyst would reject this.`);
    const nonFinite = Object.entries(this.entries).flatMap(([node, entry]) => (isObject(entry)
      ? Object.entries(entry).filter(([, v]) => hasNonFinite(v)).map(([field, v]) => `${node}.${field} (${jsText(v)})`) : []));
    if (nonFinite.length) notes.push(`Written as null, since JSON has no NaN or Infinity: ${nonFinite.join(', ')}.`);
    $('export-note').textContent = notes.join(' ');
  }

  hideExport() {
    $('export-json').hidden = true;
    $('download-export').hidden = true;
    $('copy-export').disabled = true;
    $('export-note').textContent = '';
  }

  async copyExport() {
    const area = $('export-json');
    try {
      await navigator.clipboard.writeText(area.value);
      $('export-note').textContent = 'Copied.';
    } catch {
      area.select();  // clipboard API unavailable (http, permissions): leave it selected
    }
  }
}
