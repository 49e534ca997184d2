// springbones' creator tools: deploy-time validation and the Builder edits (candidate detection,
// parameter writes), over the creator-tools module (wasm/creator_tools_bindings.cpp), a second
// WebAssembly module that a preview never downloads. sb.creatorTools() imports this file and
// loads the module on first use; the contract is springbones.d.ts (CreatorTools).
//
// The module files (dist/springbones_creator_tools.js + .wasm) are built by `scripts/build wasm`
// beside the runtime module's. The tools hold no handles: every call is a pure function of its
// arguments, and the same argument checks and errors as the runtime API's.

import { checkNonEmptyString, checkWellFormed, toBytes } from './arguments.js';
import { stringifyArgument, toJsonText } from './json_arguments.js';
import { call, takeError } from './errors.js';
import { instantiateModule } from './module_loader.js';
import { takeTyped } from './typed_output.js';
import { withBytes, withRoomForStrings } from './wasm_memory.js';

const kModuleUrl = new URL('./dist/springbones_creator_tools.wasm', import.meta.url);

/**
 * The creator tools over a new instance of their module.
 * @param {object} options createSpringBones's options, for the creator-tools module
 * @param {(where: string, options: object) => string} resolveHash the runtime's reading of which
 *   models key applies from the caller's options object, checked there (contentHash, or the
 *   entity's main file for a body shape; '' for the GLB's own hash), so that both modules choose
 *   it the same way
 */
export async function loadCreatorTools(options, resolveHash) {
  const module = await instantiateModule('creatorTools', options, {
    importGlue: () => import('./dist/springbones_creator_tools.js'),
    glueFile: 'web/dist/springbones_creator_tools.js',
    defaultUrl: kModuleUrl,
  });
  return new CreatorTools(module, resolveHash);
}

class CreatorTools {
  #m;
  #resolveHash;

  constructor(module, resolveHash) {
    this.#m = module;
    this.#resolveHash = resolveHash;
    Object.freeze(this);
  }

  /**
   * The errors a catalyst would answer for the springBones of a catalyst entity (metadata.data) or
   * of a Builder item (data, with contents): the SpringBonesData schema first, then the
   * cross-checks (models keys are mainFile hashes; bone names contain "springbone"). [] when it
   * would be accepted. Each error: {path, message}. Any other object (`{}` included) is an
   * invalid-argument error.
   */
  validateSpringBones(entity) {
    let text;
    let marker = '';
    if (typeof entity === 'string') {
      text = checkWellFormed('validateSpringBones: entity', entity);
    } else if (entity !== null && typeof entity === 'object') {
      // JSON has no NaN/Infinity; they go across as marked strings the core turns back into numbers.
      marker = nonFiniteMarker();
      text = stringifyArgument('validateSpringBones: entity', entity, { replacer: (_key, value) =>
        typeof value === 'number' && !Number.isFinite(value) ? marker + String(value) : value });
    } else {
      throw new TypeError('validateSpringBones: entity must be an object or JSON text');
    }
    const m = this.#m;
    const result = call(() => withRoomForStrings(m, [text, marker], () => m.validateSpringBones(text, marker)));
    if (result === '') throw takeError(m);
    return JSON.parse(result);
  }

  /**
   * The spring-bone candidates of a GLB (nodes whose name contains "springbone"), parents first,
   * with the values a Builder should prefill: the existing entry of springBones for this GLB's
   * models key, else the defaults. Never modifies anything.
   */
  detectSpringBones(glbBytes, springBones, options) {
    const bytes = toBytes('detectSpringBones: glbBytes', glbBytes);
    const metadataText = toJsonText('detectSpringBones: springBones', springBones, true);
    const m = this.#m;
    const hash = this.#resolveHash('detectSpringBones', options);
    const result = withBytes(m, bytes, (ptr, size) =>
      withRoomForStrings(m, [metadataText, hash], () => m.detectSpringBones(ptr, size, metadataText, hash)));
    if (result === '') throw takeError(m);
    return JSON.parse(result).candidates.map((c) => {
      const { stiffness, gravityPower, gravityDir, drag } = c.params;
      const candidate = {
        name: c.name, node: c.node, parent: c.parent, hasEntry: c.hasEntry, isRoot: c.isRoot,
        params: { stiffness, gravityPower, gravityDir, drag },
      };
      if ('center' in c) candidate.center = c.center;
      return candidate;
    });
  }

  /**
   * A new springBones object with nodeName's parameters set under the models key of the GLB that
   * bodyShape wears in the entity (params null removes the entry). One entry serves a GLB shared
   * by both body shapes; entries under hashes no representation uses are dropped; version is 1.
   * The inputs are not modified.
   */
  setSpringBoneParams(springBones, entity, bodyShape, nodeName, params) {
    // JSON would turn NaN or Infinity into null, which means something else in springBones
    // (center: null is world space), and a typed array into an object of its indices: every
    // object argument refuses them at any depth, in what a toJSON returns too.
    const metadataText = toJsonText('setSpringBoneParams: springBones', springBones, true, { finite: true });
    const entityText = toJsonText('setSpringBoneParams: entity', entity, false, { finite: true });
    checkNonEmptyString('setSpringBoneParams: bodyShape', bodyShape);
    checkNonEmptyString('setSpringBoneParams: nodeName', nodeName);
    if (params !== null && (typeof params !== 'object' || Array.isArray(params) || ArrayBuffer.isView(params))) {
      throw new TypeError('setSpringBoneParams: params must be an object, or null to remove the entry');
    }
    const paramsText = stringifyArgument('setSpringBoneParams: params', params, { finite: true });
    if (params !== null && !(typeof paramsText === 'string' && paramsText.startsWith('{'))) {
      // A toJSON that returned no object (null would remove the entry).
      throw new TypeError(`setSpringBoneParams: params must be an object, or null to remove the entry; its toJSON() gave ${paramsText}`);
    }
    const m = this.#m;
    const strings = [metadataText, entityText, bodyShape, nodeName, paramsText];
    const result = call(() => withRoomForStrings(m, strings, () => m.setSpringBoneParams(...strings)));
    if (result === '') throw takeError(m);
    return JSON.parse(result);
  }

  /** Diagnostics: the creator-tools module's memory size and the bytes requested from malloc and not freed. */
  stats() {
    const s = takeTyped(this.#m, this.#m.stats());
    return { heapBytes: this.#m.HEAPU8.byteLength, heapInUse: s.heapInUse };
  }
}

// A prefix no real string in the entity will start with: drawn at random for each call.
function nonFiniteMarker() {
  let random = '';
  for (let i = 0; i < 4; ++i) random += Math.floor(Math.random() * 0x100000000).toString(36);
  return `\u0000springbones-non-finite-${random}:`;
}
