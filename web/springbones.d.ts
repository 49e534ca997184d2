// springbones: the contract of web/springbones.js. Hand-written; keep it in step with the module.
//
// Errors: bad argument types throw TypeError, out-of-range values (non-finite dt, stepHz outside
// [1, 1000], ...) throw RangeError, both before anything reaches WebAssembly. Everything else is
// a SpringBonesError. After any error the module keeps working.

/** Error codes of SpringBonesError. Codes from the core are listed first. */
export type SpringBonesErrorCode =
  | 'invalid-argument'            // e.g. the entity has no representation for the body shape
  | 'glb-truncated'               // header or chunk extends past the end of the bytes
  | 'glb-bad-magic'               // neither a GLB nor glTF JSON text
  | 'glb-bad-chunk'               // GLB version or chunk layout not readable
  | 'gltf-bad-json'               // the glTF JSON does not parse
  | 'gltf-invalid'                // parses, but is not a usable glTF
  | 'hierarchy-multiple-parents'  // a node is the child of two parents
  | 'hierarchy-cycle'             // a node is its own ancestor
  | 'metadata-bad-json'           // springBones JSON text does not parse
  | 'metadata-invalid'            // springBones (or models, or models[hash]) is not an object
  | 'limit-exceeded'              // more nodes / bytes than the documented limits
  | 'entity-bad-json'             // entity JSON text does not parse
  | 'out-of-memory'               // WebAssembly memory could not grow
  | 'internal-error'              // a bug: please report it with the input
  | 'disposed'                    // the rig or instance was used after dispose()
  | 'module-not-found'            // web/dist/springbones_wasm.js is missing (not built)
  | 'module-load-failed';         // the .wasm could not be fetched, compiled or instantiated

export class SpringBonesError extends Error {
  constructor(code: SpringBonesErrorCode | string, message: string, path?: string);
  readonly name: 'SpringBonesError';
  readonly code: SpringBonesErrorCode | string;
  /** JSON pointer (RFC 6901) into springBones or the entity for metadata errors, else ''. */
  readonly path: string;
}

export interface CreateOptions {
  /** The .wasm bytes, when the caller has them (bundlers, service workers, tests). */
  wasmBinary?: ArrayBuffer | Uint8Array;
  /** Where the .wasm is, resolved against web/dist/springbones_wasm.wasm. Default: that file. */
  wasmUrl?: string | URL;
}

/** Loads the WebAssembly module. Node: reads the .wasm with fs; browsers: fetches it. */
export function createSpringBones(options?: CreateOptions): Promise<SpringBones>;

/** data.springBones of a wearable (ADR-316). Unknown fields are tolerated. */
export interface SpringBonesData {
  version: number;
  models: Record<string, Record<string, SpringBoneEntry>>;
}

export interface SpringBoneEntry {
  stiffness?: number;
  gravityPower?: number;
  gravityDir?: [number, number, number];
  drag?: number;
  center?: string | null;
  isRoot?: boolean | null;
}

/**
 * Which models entry of springBones applies to the GLB, by preference: the hash given; else the
 * content hash of the main file of the representation worn by bodyShape in the entity; else
 * (neither given) the GLB's own content hash, computed from its bytes.
 */
export type LoadOptions =
  | { contentHash: string }
  | {
      /** A catalyst entity {content: [{file, hash}], metadata: {data: {representations}}} or a
       *  Builder item {contents: {file: hash}, data: {representations}}, as an object or JSON text. */
      entity: object | string;
      /** Body shape URN ("urn:decentraland:off-chain:base-avatars:BaseMale") or its last segment. */
      bodyShape: string;
    }
  | Record<string, never>;

export interface SpringBones {
  /**
   * Loads a wearable once; share the rig between every avatar wearing it.
   * @param glbBytes GLB or glTF JSON bytes (copied; the caller keeps its buffer)
   * @param springBones data.springBones as an object or JSON text; null/undefined: no spring bones
   * @throws TypeError, RangeError for bad arguments; SpringBonesError for unreadable input
   */
  loadRig(glbBytes: Uint8Array | ArrayBuffer, springBones?: SpringBonesData | object | string | null,
          options?: LoadOptions): Rig;
  /** The Decentraland content hash (CIDv1, "bafk...") of the bytes, as the catalyst computes it. */
  contentHash(bytes: Uint8Array | ArrayBuffer): string;
  /** Diagnostics: live handles, the WebAssembly memory size and the bytes malloc has handed out. */
  stats(): { rigs: number; instances: number; heapBytes: number; heapInUse: number };
}

export interface BoneParams {
  readonly stiffness: number;
  readonly gravityPower: number;
  /** Unit world direction (normalised at load). */
  readonly gravityDir: readonly [number, number, number];
  readonly drag: number;
}

export interface Joint {
  /** glTF node name of the bone this joint rotates. */
  readonly name: string;
  /** glTF node index. */
  readonly node: number;
  /** Name and node index of its tail (first child): where the bone ends. */
  readonly tail: string;
  readonly tailNode: number;
  /** Index in rig.joints of the joint of the glTF parent, -1 for a chain root. */
  readonly parent: number;
  /** For a chain root: index in rig.drivers of its parent node (-1: a scene root). Else -1. */
  readonly parentDriver: number;
  /** Index in rig.drivers of the center node, -1 for world space. */
  readonly centerDriver: number;
  /** Index in rig.joints of the chain's root joint. */
  readonly chain: number;
  /** Head-to-tail distance in the rest pose, world units. */
  readonly restLength: number;
  /** Parameters in effect (own entry, else inherited, clamped and defaulted). */
  readonly params: BoneParams;
}

export interface Driver {
  /** glTF node name: the parent of a chain root or a center node. */
  readonly name: string;
  readonly node: number;
}

export interface Warning {
  /** Stable identifier, e.g. 'center-not-found', 'param-out-of-range', 'model-not-found'. */
  readonly code: string;
  readonly message: string;
  /** JSON pointer into springBones when the warning is about metadata, else ''. */
  readonly path: string;
}

export interface InstanceOptions {
  /** Fixed simulation rate in Hz, [1, 1000]. Default 60. */
  stepHz?: number;
  /** Steps per frame at most, integer in [1, 64]; surplus time of a long frame is dropped. Default 4. */
  maxSubsteps?: number;
  /** Only 'vrm' (the default) is available in this build. */
  integrator?: 'vrm';
}

/** An immutable, shareable wearable rig. Everything on it is frozen plain data. */
export interface Rig {
  /** The springBones models key the rig was built from. */
  readonly contentHash: string;
  /** Number of nodes in the GLB. */
  readonly nodeCount: number;
  /** Simulated joints, parents before children. rotations[4*i..4*i+3] belongs to joints[i]. */
  readonly joints: readonly Joint[];
  /** Indices into joints of the chain roots. */
  readonly chains: readonly number[];
  /** Nodes whose world matrices the caller provides; driverMatrices[16*i..16*i+15] is drivers[i]. */
  readonly drivers: readonly Driver[];
  /** Everything that was clamped, replaced or ignored while loading. */
  readonly warnings: readonly Warning[];
  readonly disposed: boolean;
  /** A simulation state for one avatar. @throws SpringBonesError 'disposed' after dispose() */
  createInstance(options?: InstanceOptions): Instance;
  /** Releases the rig. Its instances keep working until they are disposed. Idempotent. */
  dispose(): void;
}

/** One avatar's simulation state. */
export interface Instance {
  /**
   * Driver world matrices, column-major 4x4 (three.js Matrix4.elements order), 16 floats per
   * rig.drivers entry; write them before step(). Initially the drivers' rest world matrices.
   * A view into WebAssembly memory: read the property each frame rather than keeping the array,
   * since memory growth (loading another rig) detaches old views; the getter rebuilds it.
   */
  readonly driverMatrices: Float32Array;
  /**
   * Local rotations (x, y, z, w), relative to each joint's glTF parent, 4 floats per rig.joints
   * entry; the rest rotations until the first step. Same view rules as driverMatrices.
   */
  readonly rotations: Float32Array;
  readonly disposed: boolean;
  /**
   * Advances by a frame of dt seconds: fixed steps of 1/stepHz, at most maxSubsteps per frame.
   * dt <= 0 does nothing. The only call per frame that crosses into WebAssembly; allocates nothing.
   * @throws TypeError if dt is not a number, RangeError if it is NaN or infinite
   */
  step(dt: number): void;
  /** Forgets the motion (teleport, avatar swap): the next step starts at rest under the drivers. */
  reset(): void;
  /** Frees the instance. Idempotent; any other use afterwards throws SpringBonesError 'disposed'. */
  dispose(): void;
}
