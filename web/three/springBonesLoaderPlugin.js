// GLTFLoader plugin for springbones: loading a wearable also loads its spring-bone rig, the way
// three.js users take VRM avatars (register a plugin, then read gltf.userData):
//
//   loader.register((parser) => new SpringBonesLoaderPlugin(parser, { springBones, entity, bodyShape }));
//   const wearable = (await loader.loadAsync(url)).userData.springBones;
//   const worn = wearable.wear(avatar.scene);   // then every frame: worn.update(dt)
//
// `sb` may also be the promise createSpringBones() returns, not awaited: the GLB then loads and
// wears without waiting for the module, and the rig follows (wearable.ready, attachment.ready).
// Left out, the plugin starts the page's module itself (web/page_module.js) at the first wear():
// the page has its GLBs by then, so on a slow link the module's download never shares the
// bandwidth with them, and the API is imported then too.
//
// A thin layer over springBonesThree.js: the rig is sb.loadRig's, wearing is attachWearable on a
// SkeletonUtils clone of the loaded scene, and what wear() returns is the adapter's attachment.
//
// Which springBones.models entry applies is keyed by the GLB's content hash, which needs the
// file's exact bytes, and GLTFLoader does not hand a plugin the bytes it fetched. So the caller
// names the hash, as loadRig's options do: `contentHash`, or `entity` + `bodyShape` (the
// entity's content list has the hash; a page that shows a catalyst's wearable has the entity),
// or `glb`, the bytes it parsed (hashed with sb.contentHash). Either way the rig is read from the
// glTF JSON the parser already holds (parser.json), handed over as it is: no second parse.
//
// The 'dcl-body' colliders are measured on the avatar's bones (docs/semantics.md, "Body
// colliders"), and the avatar is known only at wear(): the rig loaded with the file measures on
// the GLB's bones, and wear() loads the rig again with the avatar's (avatarRestBones), once per
// armature: every avatar with the same bones at the same rest pose (clones, one body shape) shares
// that rig, as they share the wearable's.

import { clone as cloneWithSkeletons } from 'three/examples/jsm/utils/SkeletonUtils.js';
import { pageModule } from '../page_module.js';
import { attachWearable, attachmentDisposed, avatarRestBones, isThenable, kWearableContext, wearableNodes } from './springBonesThree.js';
import { avatarBonesKey, measuresOnAvatar, withAvatarBones } from '../wearable/avatar_bones.js';
import { consoleReporter, failureDiagnostic, rigDiagnostics } from '../wearable/diagnostics.js';
import { modelsEntry } from '../wearable/wearable_entry.js';
import { checkOptionKeys, liveEdit, loadRigOptionsOf, loadWearableRig } from '../wearable/rig_life.js';

const kHashOptions = ['contentHash', 'entity', 'bodyShape'];

export class SpringBonesLoaderPlugin {
  /**
   * parser: GLTFLoader's parser (the argument of loader.register's callback).
   * options: { sb?, springBones?, glb?, onWarning?, instance?, ...loadRig's options }:
   * sb is the module from createSpringBones() or the promise of it (the load then does not wait
   * for the module: the rig follows, see SpringBonesWearable.ready), or left out: the page's
   * module, started at the first wear(); springBones the wearable's data.springBones
   * (object or JSON text; null or left out: no spring bones); glb the bytes being parsed (they
   * name the models entry by their hash); instance the default createInstance options of wear().
   * Every other key goes to sb.loadRig as it is (contentHash, entity + bodyShape, colliders,
   * limits, hitRadius, ...), which checks it: a key it does not know fails the load with its
   * TypeError.
   */
  constructor(parser, options) {
    if (typeof parser?.json !== 'object' || parser.json === null) {
      throw new TypeError('SpringBonesLoaderPlugin: parser must be GLTFLoader\'s parser (the argument of loader.register\'s callback)');
    }
    if (options === null || typeof options !== 'object') {
      throw new TypeError('SpringBonesLoaderPlugin: options must be an object ({ springBones, entity, bodyShape, ... })');
    }
    if (options.onWarning !== undefined && typeof options.onWarning !== 'function') {
      throw new TypeError('SpringBonesLoaderPlugin: options.onWarning must be a function (it receives each warning)');
    }
    if (options.sb !== undefined && typeof options.sb?.loadRig !== 'function' && !isThenable(options.sb)) {
      throw new TypeError('SpringBonesLoaderPlugin: options.sb must be the springbones module or its promise (the result of createSpringBones()), or left out');
    }
    const hasSpringBones = options.springBones !== undefined && options.springBones !== null;
    if (hasSpringBones && options.glb === undefined && kHashOptions.every((k) => options[k] === undefined)) {
      throw new TypeError('SpringBonesLoaderPlugin: springBones.models is keyed by the GLB\'s content hash: ' +
          'pass contentHash, entity + bodyShape, or glb (the bytes being parsed)');
    }
    this.name = 'springbones';
    this.parser = parser;
    this.options = options;
  }

  /** GLTFLoader's hook once the scene is built: loads the rig into gltf.userData.springBones. */
  async afterRoot(gltf) {
    const { springBones } = this.options;
    const page = this.options.sb === undefined ? pageModule() : null;
    const sb = page?.promise ?? this.options.sb;
    const rigOptions = loadRigOptionsOf(this.options);
    // The rig needs only the nodes, which the JSON GLTFLoader parsed has: it goes to loadRig as it
    // is (no second parse). The bytes, when given, only name the models key by their hash.
    const json = this.parser.json;
    let loadedWith = null;  // the module, once the rig is loaded: live updates load with it
    const load = (module) => {
      if (typeof module?.loadRig !== 'function') {
        throw new TypeError('SpringBonesLoaderPlugin: options.sb resolved to something other than the springbones module');
      }
      const rig = loadWearableRig(module, json, springBones, rigOptions);
      loadedWith = module;
      return rig;
    };
    // The module itself: the rig now (its errors reject the load). Its promise: the load goes on,
    // and a module that fails is told apart from a rig that fails (their fixes differ).
    const rig = isThenable(sb)
      ? Promise.resolve(sb).then(load, (error) => Promise.reject(new ModuleFailure(error)))
      : load(sb);
    const { entity, contentHash, onWarning, instance } = this.options;
    gltf.userData.springBones = new SpringBonesWearable(gltf, rig, {
      springBones, rigOptions, instance, onWarning, label: entity?.metadata?.id ?? entity?.id ?? contentHash ?? null,
      startModule: page?.start, module: () => loadedWith,
    });
  }
}

// The module's own error, marked as the module's (not loadRig's) on the way to the wearable.
class ModuleFailure {
  constructor(error) {
    this.error = error;
  }
}

/**
 * gltf.userData.springBones, typed (see the .d.ts: three's GLTF['userData'] is
 * Record<string, any> and cannot be narrowed): the SpringBonesWearable the plugin put there, or null.
 */
export function springBonesOf(gltf) {
  const wearable = gltf?.userData?.springBones;
  return wearable instanceof SpringBonesWearable ? wearable : null;
}

/**
 * A loaded wearable with its rig: what SpringBonesLoaderPlugin puts on gltf.userData.springBones.
 * The loaded scene stays a template: each wear() attaches a clone of it, so one load serves any
 * number of avatars, all sharing the rig.
 */
export class SpringBonesWearable {
  #rigOptions; #instanceOptions; #module; #startModule; #staticHair; #failure;
  #springBones; #report; #disposed; #rigPromise; #avatarRigs;

  /** @private made by SpringBonesLoaderPlugin */
  constructor(gltf, rig, { springBones = null, rigOptions = {}, instance = undefined, label = null, onWarning = undefined, startModule = null, module = () => null } = {}) {
    this.gltf = gltf;
    this.#rigOptions = rigOptions;  // loadRig's, for live updates
    this.#instanceOptions = instance;  // wear()'s default createInstance options
    this.#module = module;
    this.#startModule = startModule;  // the page's module, when the plugin was given none
    // Why the spring bones would stay at rest (docs/diagnostics.md), said once per wearable however
    // many avatars wear it: the attachments wear() makes share this reporter.
    this.#staticHair = [];
    this.#failure = null;
    this.#springBones = springBones;
    this.#report = onWarning ?? consoleReporter(() => `wearable ${label ?? this.rig?.contentHash ?? '(loading)'}`);
    /** The springbones rig (joints, chains, drivers, warnings); owned: dispose() frees it. Null
     *  while the module given as a promise has not resolved. */
    this.rig = null;
    /** The attachments wear() made and dispose() has not yet disposed of. */
    this.attachments = [];
    /** What loading the rig failed with, when the module came as a promise; else null. */
    this.error = null;
    this.#disposed = false;
    // avatarBonesKey -> { bones, rig }: the rigs measured on the avatars worn so far ('dcl-body'),
    // a rig or, before the module is there, the promise of one.
    this.#avatarRigs = new Map();
    if (isThenable(rig)) {
      this.#rigPromise = rig.then((arrived) => {
        if (this.#disposed) arrived.dispose();
        else this.#arrived(arrived);
        return arrived;
      }, (failure) => {
        const error = failure instanceof ModuleFailure ? failure.error : failure;
        this.#failed(failureDiagnostic(error, failure instanceof ModuleFailure));
        throw error;
      });
      /** Resolves to this wearable once its rig is loaded; rejects with the module's or loadRig's error. */
      this.ready = this.#rigPromise.then(() => this, (error) => {
        this.error = error;
        throw error;
      });
      // Both said on the console (#failed): an application that catches neither gets the warning,
      // not an unhandled rejection (which ends a Node process).
      this.#rigPromise.catch(() => {});
      this.ready.catch(() => {});
    } else {
      this.#rigPromise = null;
      this.#arrived(rig);
      this.ready = Promise.resolve(this);
    }
  }

  #arrived(rig) {
    this.rig = rig;
    const found = this.#diagnose(rig);
    for (const warning of found) this.#report(warning);
    this.#staticHair = found.filter((w) => !rig.warnings.some((own) => own.code === w.code));  // the core's are listed already
  }

  /** What leaves this rig's hair at rest, from the metadata the plugin was given (diagnostics.js). */
  #diagnose(rig) {
    const springBones = this.#springBones;
    const entry = springBones === null ? null : modelsEntry(springBones, rig.contentHash);
    return rigDiagnostics({ rig, springBones, entry, nodes: this.gltf.parser?.json?.nodes ?? [] });
  }

  #failed(warning) {
    this.#failure = warning;
    this.#staticHair = [warning];
    this.#report(warning);
  }

  /**
   * The rig's warnings (clamped parameters, a models entry not found, ...), then the reasons the
   * spring bones stay at rest that the rig does not list itself (no chain root, a module or rig
   * that failed: docs/diagnostics.md, each with a `fix`). Empty before the rig loads.
   */
  get warnings() {
    // Measured on each avatar when worn, the body's shapes do not depend on the bones the GLB
    // lacks: what an avatar lacks is in its attachment's rig.warnings.
    const own = measuresOnAvatar(this.#rigOptions)
      ? (this.rig?.warnings ?? []).filter((w) => w.code !== 'body-collider-skipped')
      : (this.rig?.warnings ?? []);
    return [...own, ...this.#staticHair];
  }

  /**
   * The rig an attachment on `avatarRoot` runs: with 'dcl-body' colliders (and no avatarBones
   * given), the one measured on the avatar's bones, shared by every avatar of the same bones;
   * else, or for an avatar without skins, the wearable's. A rig or, before the module is there,
   * the promise of one.
   */
  #rigFor(avatarRoot) {
    const bones = measuresOnAvatar(this.#rigOptions) ? avatarRestBones(avatarRoot) : null;
    if (bones === null) return this.rig ?? this.#rigPromise;
    const key = avatarBonesKey(bones);
    let worn = this.#avatarRigs.get(key);
    if (worn === undefined) {
      worn = { bones, rig: null };
      if (this.rig !== null) {
        worn.rig = this.#loadOn(bones);  // throws what loadRig throws, with nothing kept
      } else {
        worn.rig = this.#rigPromise.then(() => {
          if (this.#disposed) return this.rig;  // the attachments are disposed of too
          worn.rig = this.#loadOn(bones);
          return worn.rig;
        });
      }
      this.#avatarRigs.set(key, worn);
    }
    return worn.rig;
  }

  /** The rig with the current metadata and options, measured on `bones` (an avatar's). */
  #loadOn(bones, springBones = this.#springBones, options = this.#rigOptions) {
    return loadWearableRig(this.#module(), this.gltf.parser.json, springBones, withAvatarBones(options, bones));
  }

  /**
   * Wears a clone of the wearable on an avatar (see attachWearable for the matching by bone name)
   * and returns the attachment: call its update(dt) every frame after the avatar's world matrices
   * are current, or add it to a SpringBonesGroup. options.instance: rig.createInstance's options.
   */
  wear(avatarRoot, options = {}) {
    if (options === null || typeof options !== 'object') throw new TypeError('wear: options must be an object');
    checkOptionKeys('wear', options, ['instance', 'mixer', 'onWarning']);
    this.#startModule?.();
    const copy = cloneWithSkeletons(this.gltf.scene);
    // Before the rig is there, the attachment is worn and drawn and simulates once it arrives.
    const rig = this.#rigFor(avatarRoot);
    const attachment = attachWearable(avatarRoot, copy, rig, {
      instance: this.#instanceOptions,
      ...options,
      nodes: wearableNodes(this.gltf, copy),
      [kWearableContext]: {
        report: this.#report,
        diagnose: (r) => this.#diagnose(r),
        failure: () => this.#failure,  // the wearable's own reading of the failure (module or rig)
      },
    });
    this.attachments.push(attachment);
    return attachment;
  }

  /**
   * The Builder's live tuning, as the Babylon drop-in's updateParams: `params` (node name ->
   * parameters, the whole models entry) is merged over the current entry (a non-finite number
   * keeps the previous value; names left out are dropped), the rig is loaded again with the same
   * options, and every attachment switches to it keeping its motion (attachment.setRig carries
   * it: the chains neither pop nor restart). The previous rig is disposed of.
   * @throws TypeError for params that are not an object; Error before the rig is there (await
   *   `ready`); what loadRig throws for the edited entry, with nothing changed
   */
  updateParams(params) {
    if (params === null || typeof params !== 'object' || Array.isArray(params)) {
      throw new TypeError('updateParams: params must be an object of node name -> parameters');
    }
    const module = this.#module();
    if (this.rig === null || module === null || this.#disposed) {
      throw new Error(`updateParams: ${this.#disposed ? 'the wearable is disposed of' : 'the rig is not loaded yet (await wearable.ready)'}`);
    }
    const { springBones, options } = liveEdit(this.#springBones, this.rig.contentHash, this.#rigOptions, params);
    // Every rig again, the wearable's and each avatar's, before anything changes (a throw leaves all as it was).
    const next = new Map([[this.rig, loadWearableRig(module, this.gltf.parser.json, springBones, options)]]);
    try {
      for (const worn of this.#avatarRigs.values()) {
        // One still on its way loads with the edited metadata when it arrives (#loadOn reads it then).
        if (!isThenable(worn.rig)) next.set(worn.rig, this.#loadOn(worn.bones, springBones, options));
      }
    } catch (error) {
      for (const rig of next.values()) rig.dispose();
      throw error;
    }
    this.#springBones = springBones;
    this.#rigOptions = options;
    for (const attachment of this.attachments) {
      if (!attachmentDisposed(attachment) && next.has(attachment.rig)) attachment.setRig(next.get(attachment.rig));
    }
    for (const worn of this.#avatarRigs.values()) if (next.has(worn.rig)) worn.rig = next.get(worn.rig);
    const previous = [...next.keys()];
    this.#arrived(next.get(this.rig));
    for (const rig of previous) rig.dispose();
  }

  /**
   * Disposes of every attachment wear() made (taking the clones off their avatars) and of the
   * rig. The geometries and materials, shared with gltf.scene, are the caller's.
   */
  dispose() {
    for (const attachment of this.attachments) {
      if (attachment.instance === null || !attachment.instance.disposed) attachment.dispose();
    }
    this.attachments = [];
    this.#disposed = true;  // a rig still on its way is disposed of when it arrives
    if (this.rig !== null) this.rig.dispose();
    for (const worn of this.#avatarRigs.values()) if (!isThenable(worn.rig) && !worn.rig.disposed) worn.rig.dispose();
    this.#avatarRigs.clear();
  }
}
