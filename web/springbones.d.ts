// springbones: the contract of web/springbones.js. Hand-written; keep it in step with the module.
//
// Errors: bad argument types throw TypeError, out-of-range values (non-finite dt, stepHz outside
// [1, 1000], ...) throw RangeError, both before anything reaches WebAssembly. Everything else is
// a SpringBonesError. After any error the module keeps working. In every argument, a hole or an
// undefined element in an array (at any depth of an object that crosses as JSON) and a typed
// array inside such an object are a TypeError; a string with a lone surrogate (a name, a hash, a
// key or value inside an object, JSON text) is a RangeError: it has no UTF-8 form.

/** Error codes of SpringBonesError. Codes from the core are listed first. */
export type SpringBonesErrorCode =
  | 'invalid-argument'            // e.g. the entity has no representation for the body shape, or an
                                  // object argument nests too deeply for JSON.stringify (thousands of levels)
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
  | 'params-bad-json'             // setSpringBoneParams: params JSON does not parse (not reachable from objects)
  | 'out-of-memory'               // WebAssembly memory could not grow
  | 'internal-error'              // a bug: please report it with the input
  | 'disposed'                    // the rig, instance or scene was used after dispose()
  | 'readers-not-loaded'          // loadRig was given bytes, or loadVrm called, in a browser
                                  // before `await sb.readers()` (or the readers module failed to load)
  | 'module-not-found'            // a module's glue (web/dist/springbones_wasm.js,
                                  // springbones_readers.js or springbones_creator_tools.js) is missing (not built)
  | 'module-load-failed';         // the .wasm could not be fetched, compiled or instantiated

export class SpringBonesError extends Error {
  constructor(code: SpringBonesErrorCode | string, message: string, path?: string);
  readonly name: 'SpringBonesError';
  readonly code: SpringBonesErrorCode | string;
  /** JSON pointer (RFC 6901) into springBones or the entity for metadata errors, else ''. */
  readonly path: string;
}

export interface CreateOptions {
  /**
   * The module, from a download the page started itself, so that it runs in parallel with the
   * page's other fetches and with the import of this library: a Response (compiled while it
   * streams when served as application/wasm), a WebAssembly.Module, or a promise of either, e.g.
   * `createSpringBones({ wasm: fetch(moduleUrl) })` with `moduleUrl` the URL of
   * dist/springbones_wasm.wasm (the package's `springbones/wasm` export). A failed download or
   * compile rejects with SpringBonesError 'module-load-failed', whose message names what was read
   * (the wasm option or the Response's URL, the wasmBinary option, the inline module, or the URL
   * fetched) and what came back: the HTTP status, the content type when it is not
   * application/wasm, how bytes that are not WebAssembly begin (an HTML page served in its
   * place). At most one of wasm, wasmBinary and wasmUrl.
   */
  wasm?: Response | WebAssembly.Module | PromiseLike<Response | WebAssembly.Module>;
  /** The .wasm bytes, when the caller has them (bundlers, service workers, tests). */
  wasmBinary?: ArrayBuffer | Uint8Array;
  /**
   * Where the .wasm is, resolved against the default: web/dist/springbones_wasm.wasm for
   * createSpringBones (web/dist/springbones_crowd.wasm with `crowd: true`),
   * web/dist/springbones_creator_tools.wasm for sb.creatorTools().
   */
  wasmUrl?: string | URL;
  /**
   * createSpringBones only: load the crowd module (dist/springbones_crowd.wasm, the package's
   * `springbones/crowd-wasm` export) instead of the runtime. The same API, the same rotations bit
   * for bit; its per-frame code is built for speed, so it steps a crowd 3-4 times faster, and it
   * is 18 KB gzip more to download. A page that shows one avatar (a preview) does not need it; a
   * page with a crowd asks for it. Default false. With wasm, wasmBinary or wasmUrl, the module
   * given is the one that runs.
   */
  crowd?: boolean;
}

/**
 * Loads the runtime WebAssembly module. Node: reads the .wasm with fs; browsers: fetches it. In a
 * browser, the first idle period after it resolves loads, steps and frees a built-in two-joint
 * rig (requestIdleCallback), so that compiling the load path is not part of the page's first
 * loadRig; nothing of it remains (stats() is as before).
 */
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
export type HashOptions =
  | { contentHash?: string }
  | {
      /** A catalyst entity {content: [{file, hash}], metadata: {data: {representations}}} or a
       *  Builder item {contents: {file: hash}, data: {representations}}, as an object or JSON text. */
      entity: object | string;
      /** Body shape URN ("urn:decentraland:off-chain:base-avatars:BaseMale") or its last segment. */
      bodyShape: string;
    };

/**
 * A collision shape on a node, in that node's space: a sphere, a capsule (offset to tail, swept by
 * radius) or a plane (through offset, facing normal). Node units, not metres: on Decentraland's
 * armature, scaled 0.01, a bone's units are centimetres (a 9.5 cm head sphere on Avatar_Head is
 * radius 9.5); the 'dcl-body' preset is sized from the armature itself. Without `shape`, a collider with a `tail` is
 * a capsule and one without a sphere. `node` is a GLB node, or an avatar bone the GLB does not
 * have (e.g. 'Avatar_Head'), which then becomes a driver (node -1) whose world matrix the caller
 * writes. A key that does not belong to the shape (a sphere's `tail`, a plane's `radius`) is a
 * TypeError.
 */
export interface ColliderOptions {
  node: string;
  /** Default: 'capsule' when `tail` is given, else 'sphere'. */
  shape?: 'sphere' | 'capsule' | 'plane';
  /** Sphere centre / capsule start / a point of the plane, finite. Default [0, 0, 0]. */
  offset?: readonly [number, number, number] | Float32Array | Float64Array;
  /** Sphere and capsule (required for them): finite, >= 0, in the node's space (scaled with it).
   *  A radius, offset or tail component beyond 1e6 leaves the collider out (warning `collider-invalid`). */
  radius?: number;
  /** Capsule end, finite. Default [0, 0, 0]. */
  tail?: readonly [number, number, number] | Float32Array | Float64Array;
  /** Plane: the side joints are kept on, finite, not [0, 0, 0] (made unit, whatever its size). Default [0, 0, 1]. */
  normal?: readonly [number, number, number] | Float32Array | Float64Array;
  /** Sphere and capsule: keep the joints' tails inside the shape (radius - hitRadius from its
   *  centre or axis) instead of outside it. Default false. */
  inside?: boolean;
}

/**
 * A ready-made collider set. 'dcl-body' (a preview option, not part of the standard): a head
 * sphere and capsules for the neck, chest, shoulders and upper arms, built from the rest pose of
 * the Decentraland armature bones, sized from their rest lengths (docs/semantics.md, "Body
 * colliders"): the avatar's bones when `avatarBones` gives them (both adapters give them when a
 * wearable is worn), else those the GLB carries. Shapes whose bones are missing are left out with a `body-collider-skipped` warning.
 */
export type ColliderPreset = 'dcl-body';

/** The name of a 'dcl-body' shape, for SetCollidersOptions.omit. */
export type BodyShapeName =
  | 'head' | 'neck' | 'chest' | 'upper-belly' | 'left-shoulder' | 'right-shoulder' | 'left-upper-arm' | 'right-upper-arm';

/** instance.setColliders' options. */
export interface SetCollidersOptions {
  /** As LoadOptions.avatarBones: the avatar's bones the 'dcl-body' shapes are measured on and ride on. */
  avatarBones?: Readonly<Record<string, readonly number[] | Float32Array | Float64Array>>;
  /** 'dcl-body' only: every shape's radius times this (finite, >= 0; 0.5 halves them). The capsules
   *  still run between their bones: lengths are the avatar's. Default 1. */
  scale?: number;
  /** 'dcl-body' only: the shapes to leave out, by name. */
  omit?: readonly BodyShapeName[];
}

/**
 * An angle limit on a joint, as VRMC_springBone_limit (1.0-draft) spells it: exactly one of cone,
 * hinge and spherical (docs/semantics.md, "Angle limits"). Angles are radians, finite; a negative
 * one, or one beyond its maximum (pi; yaw pi/2), is clamped with a `limit-clamped` warning.
 * `rotation` (x, y, z, w; default the identity) turns the limit from its default orientation,
 * whose +Y is the joint's rest bone direction; it is made unit.
 */
export type JointLimit =
  | { cone: { angle: number; rotation?: readonly [number, number, number, number] } }
  | { hinge: { angle: number; rotation?: readonly [number, number, number, number] } }
  | { spherical: { pitch: number; yaw: number; rotation?: readonly [number, number, number, number] } };

export type LoadOptions = HashOptions & {
  /** Colliders every joint collides with (none by default), or a preset's name. The GLB is not touched. */
  colliders?: readonly ColliderOptions[] | ColliderPreset;
  /**
   * The bones of the avatar the wearable is worn on, by name, with their rest world matrices (16
   * finite numbers within +-1e12, column-major: three.js's `Matrix4.elements`). With
   * `colliders: 'dcl-body'` every shape is measured on these, not on the bones the GLB carries, and
   * rides on the avatar's bone of its name (a driver in `rig.drivers` the page supplies each frame
   * when the GLB lacks it), so a hair wearable that carries Hips to Head still gets its shoulder and
   * arm shapes. The adapters pass the avatar's. Wrong types are a TypeError, a non-finite or
   * larger entry a RangeError.
   */
  avatarBones?: Readonly<Record<string, readonly number[] | Float32Array | Float64Array>>;
  /** Radius of each joint's tail against the colliders, world units, finite, >= 0. Default 0.
   *  Beyond 1e6 it is clamped there, with the rig warning `hit-radius-out-of-range`. */
  hitRadius?: number;
  /**
   * Angle limits by joint node name (the standard's metadata has none). A name that is no simulated
   * joint is ignored with a warning (`limit-joint-not-found`, or `limit-on-end-joint` for a chain's
   * tip). A rig with a limit steps on the general path, not the lane path.
   */
  limits?: { readonly [jointName: string]: JointLimit };
  /** Default jumpDistance of the rig's instances (InstanceOptions; createInstance's overrides it). */
  jumpDistance?: number;
  /** Default jumpAngle of the rig's instances (InstanceOptions; createInstance's overrides it). */
  jumpAngle?: number;
};

/** A spring-bone candidate of a GLB for the Builder, with the values to prefill. */
export interface SpringBoneCandidate {
  /** Node name; it contains "springbone" (ASCII case-insensitive). */
  name: string;
  /** glTF node index. */
  node: number;
  /** Index in the returned list of the nearest candidate ancestor, -1 for none. */
  parent: number;
  /** springBones already has an entry for this node (under the GLB's models key). */
  hasEntry: boolean;
  /** The entry's isRoot; without an entry, true for the top-most candidates. */
  isRoot: boolean;
  /** The entry's values as the runtime reads them (clamped, gravityDir normalised), else the defaults. */
  params: { stiffness: number; gravityPower: number; gravityDir: [number, number, number]; drag: number };
  /** Present when the entry has a center: a node name, or null for world space. */
  center?: string | null;
}

/** What setSpringBoneParams writes for one node; other keys are kept as given. */
export interface SpringBoneParamsInput extends SpringBoneEntry {
  [key: string]: unknown;
}

/** One reason a catalyst would reject the deployment. */
export interface ValidationError {
  /** JSON pointer into springBones ('' for springBones itself), or into the entity for entity-structure errors. */
  path: string;
  /** The catalyst's message, e.g. "springBones/models/<hash>/<bone>/drag must be <= 1". */
  message: string;
}

/** A parsed glTF document, as a loader holds it (three.js: `gltf.parser.json`). */
export interface GltfJson {
  asset?: { version?: string; [key: string]: unknown };
  nodes?: object[];
  extensions?: object;
  [key: string]: unknown;
}

export interface SpringBones {
  /** The package version, equal to the installed package.json's `version` (semver, 0.x). */
  readonly version: string;
  /**
   * True for the crowd module (createSpringBones({ crowd: true })), built to step many instances
   * fast; false for the runtime. Rotations are the same either way.
   */
  readonly crowd: boolean;
  /**
   * Loads a wearable once; share the rig between every avatar wearing it.
   * @param glb the glTF JSON the page's loader already parsed (three.js: `gltf.parser.json`; only
   *   its `asset` and its nodes' name, children and transforms are read), or GLB / glTF JSON bytes
   *   (copied; read by the readers module: in a browser, `await sb.readers()` first, else a
   *   'readers-not-loaded' error). With the parsed JSON there are no bytes to hash: name the models
   *   entry with `contentHash` or `entity` + `bodyShape` (else a TypeError, unless springBones is
   *   null or undefined).
   * @param springBones data.springBones (e.g. `entity.metadata.data.springBones`) as an object,
   *   handed over as it is (no JSON.stringify; NaN and Infinity stay numbers and earn the core's
   *   'param-not-finite' warning), or its JSON text; null/undefined: no spring bones
   * @throws TypeError, RangeError for bad arguments; SpringBonesError for unreadable input
   */
  loadRig(glb: GltfJson | Uint8Array | ArrayBuffer, springBones?: SpringBonesData | object | string | null,
          options?: LoadOptions | null): Rig;
  /**
   * Loads the spring bones of a VRM avatar: VRMC_springBone 1.0 (preferred when both are present)
   * or VRM 0.x secondaryAnimation, with their colliders. Same Rig interface; contentHash is ''.
   * A file with neither gives an empty rig with a 'vrm-no-springs' warning. The VRM rules run in
   * the readers module (a preview of wearables never downloads them): in a browser,
   * `await sb.readers()` first, else a 'readers-not-loaded' error, whichever the input.
   * @param vrm the glTF JSON a loader parsed (its asset, nodes and root extensions are read), or
   *   the .vrm bytes
   */
  loadVrm(vrm: GltfJson | Uint8Array | ArrayBuffer): Rig;
  /**
   * The readers module, which reads GLB and VRM bytes for loadRig and loadVrm and runs loadVrm's
   * VRM rules (dist/springbones_readers.wasm, the package's `springbones/readers-wasm`). In Node,
   * createSpringBones() loads it; in a browser a page that has bytes to read, or VRM avatars to
   * load, awaits this first (a page that hands loadRig its loader's parse never needs it). Every later call resolves with the
   * same module; a failed load rejects ('module-load-failed') and the next call tries again.
   */
  readers(options?: CreateOptions): Promise<void>;
  /** The Decentraland content hash (CIDv1, "bafk..."/"bafy...") of the bytes, as the catalyst computes it. */
  contentHash(bytes: Uint8Array | ArrayBuffer): string;
  /**
   * The creator tools: deploy-time validation and the Builder edits (validateSpringBones,
   * detectSpringBones, setSpringBoneParams). They are a second WebAssembly module
   * (dist/springbones_creator_tools.wasm, the package's `springbones/creator-tools-wasm`) that
   * createSpringBones() never downloads: the first call downloads and starts it, every later call
   * resolves to the same object (the first call's options apply). The options are
   * createSpringBones's, for this module: a page can start the download itself and hand it over.
   * A failed load rejects with SpringBonesError 'module-load-failed' ('module-not-found' when the
   * glue is missing) and the next call tries again.
   */
  creatorTools(options?: CreateOptions): Promise<CreatorTools>;
  /** A scene for stepping many instances in one call. */
  createScene(): Scene;
  /**
   * Diagnostics: live handles, the WebAssembly memory size, and in heapInUse the bytes requested
   * from malloc and not yet freed (what was asked for, not the allocator's blocks: the same after
   * two identical loads, back to its value once what they made is disposed).
   */
  stats(): { rigs: number; instances: number; scenes: number; heapBytes: number; heapInUse: number };
}

/** What sb.creatorTools() resolves to: the tools a creator (Builder) uses, never a preview. */
export interface CreatorTools {
  /**
   * The errors a catalyst would answer for the entity's data.springBones ([] when accepted):
   * the SpringBonesData schema of @dcl/schemas first (NaN and Infinity are "must be number"), then
   * every models key must be the main file hash of a current representation and every bone name
   * must contain "springbone". Absent or null springBones is valid. Members whose value is
   * undefined are dropped, as in JSON.
   * @param entity a catalyst entity `{content, metadata: {data}}` or a Builder item
   *   `{contents, data}` (see HashOptions), validated alike, as an object or JSON text
   * @throws TypeError when entity is neither an object nor a string
   * @throws SpringBonesError 'entity-bad-json' for JSON text that does not parse;
   *   'invalid-argument' for a value of neither shape (`{}` included), which is never answered []
   */
  validateSpringBones(entity: object | string): ValidationError[];
  /**
   * The nodes of a GLB whose name contains "springbone", parents first, with prefill values from
   * springBones' entry for the GLB (chosen as in loadRig). Reads the bytes; changes nothing.
   */
  detectSpringBones(glbBytes: Uint8Array | ArrayBuffer, springBones?: SpringBonesData | object | string | null,
                    options?: HashOptions | null): SpringBoneCandidate[];
  /**
   * A new springBones with models[hash][nodeName] = params (null removes the entry), hash being the
   * main file hash of bodyShape's representation: one entry for a GLB both body shapes share.
   * Entries under hashes no representation uses are dropped; version becomes 1. The inputs and
   * the GLB are not modified.
   * @throws RangeError for non-finite numbers at any depth of springBones, entity or params (as
   * their toJSON() give them too), or a lone surrogate in any string; TypeError for a typed array,
   * a hole or an undefined element in an array at any depth; SpringBonesError 'invalid-argument' for a
   * node name without "springbone", an unknown body shape, or params nested more than 64 levels
   */
  setSpringBoneParams(springBones: SpringBonesData | object | string | null | undefined, entity: object | string,
                      bodyShape: string, nodeName: string, params: SpringBoneParamsInput | null): SpringBonesData;
  /**
   * Diagnostics of the creator-tools module: its memory size, and in heapInUse the bytes requested
   * from malloc and not yet freed.
   */
  stats(): { heapBytes: number; heapInUse: number };
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
  /**
   * Name and node index of its tail (first child): where the bone ends. null and -1 when the tail
   * is no node (a VRM 0.x leaf's virtual tail); tailOffset is always right.
   */
  readonly tail: string | null;
  readonly tailNode: number;
  /** The tail in the joint's local space. */
  readonly tailOffset: readonly [number, number, number];
  /** Radius of the tail against the colliders, world units. */
  readonly hitRadius: number;
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
  /**
   * Its angle limit as in effect (clamped, rotation made unit; spherical limits always say pitch and
   * yaw), or null: from VRMC_springBone_limit in a VRM file, or loadRig's `limits`.
   */
  readonly limit: {
    readonly cone?: { readonly angle: number; readonly rotation: readonly [number, number, number, number] };
    readonly hinge?: { readonly angle: number; readonly rotation: readonly [number, number, number, number] };
    readonly spherical?: {
      readonly pitch: number;
      readonly yaw: number;
      readonly rotation: readonly [number, number, number, number];
    };
  } | null;
}

export interface Driver {
  /** Node name: the parent of a chain root, a center node or a collider's node. */
  readonly name: string;
  /** glTF node index; -1 for a node the GLB does not have (a collider on an avatar bone). */
  readonly node: number;
}

export interface Collider {
  /** Index in rig.drivers of the node carrying it. */
  readonly driver: number;
  /** That driver's name. */
  readonly node: string;
  readonly shape: 'sphere' | 'capsule' | 'plane';
  /** Sphere and capsule: tails are kept inside the shape rather than outside. False for planes. */
  readonly inside: boolean;
  /** Sphere centre / capsule start / a point of the plane in the node's space. */
  readonly offset: readonly [number, number, number];
  /** Capsule end in the node's space (capsules only). */
  readonly tail?: readonly [number, number, number];
  /** Unit normal of a plane in the node's space (planes only). */
  readonly normal?: readonly [number, number, number];
  /** In the node's space; 0 for a plane. */
  readonly radius: number;
}

export interface Warning {
  /** Stable identifier, e.g. 'center-not-found', 'param-out-of-range', 'model-not-found'. */
  readonly code: string;
  readonly message: string;
  /** JSON pointer into springBones when the warning is about metadata, else ''. */
  readonly path: string;
}

export interface InstanceOptions {
  /** Fixed simulation rate in Hz, [1, 1000]. Default 60; 120 with integrator 'xpbd'. */
  stepHz?: number;
  /** Steps per frame at most, integer in [1, 64]; surplus time of a long frame is dropped. Default 4; 8 with 'xpbd'. */
  maxSubsteps?: number;
  /**
   * 'vrm' (default): the VRM spring-bone update. 'xpbd': the XPBD integrator (exact bone lengths,
   * compliant constraints, collisions as constraints) driven by the same parameters.
   */
  integrator?: 'vrm' | 'xpbd';
  /** 'xpbd' only: constraint passes per substep, integer in [1, 64]. Default 4. RangeError with 'vrm'. */
  xpbdIterations?: number;
  /**
   * A driver translating farther than this in one frame, in world units (metres) per fixed step
   * of the frame, is a jump (a teleport, a cut): the chains are carried across it (instance.jump).
   * Finite, >= 0; 0 turns this test off. Default 0.5 (30 m/s at 60 Hz). Default for loadRig's
   * instances when given there.
   */
  jumpDistance?: number;
  /** The same for a driver's turn, radians per step; 0 turns it off. Default 0.5 (about 1,700 degrees/s at 60 Hz). */
  jumpAngle?: number;
  /**
   * How much of the motion of the driver a chain hangs from its chains feel, [0, 1]: 1 (default)
   * all of it, the VRM update bit for bit; 0 none, as if each chain's inertia were kept in that
   * driver's space (hair calm in a vehicle or on a platform). Below 1 the instance takes the
   * general path (slower than the lane path). instance.setInertia sets one chain.
   * @throws RangeError outside [0, 1]
   */
  inertia?: number;
}

/**
 * An immutable, shareable wearable rig. Everything on it is frozen plain data. The lists (joints,
 * chains, drivers, colliders, warnings) are built on their first read, then the same objects on
 * every read, and stay readable after dispose().
 */
export interface Rig {
  /** The springBones models key the rig was built from ('' for loadVrm). */
  readonly contentHash: string;
  /** Where the springs came from: data.springBones ('dcl'), VRMC_springBone 1.0, VRM 0.x, or nothing. */
  readonly format: 'dcl' | 'vrmc-springbone' | 'vrm0' | 'none';
  /** Number of nodes in the GLB. */
  readonly nodeCount: number;
  /** Simulated joints, parents before children. rotations[4*i..4*i+3] belongs to joints[i]. */
  readonly joints: readonly Joint[];
  /** Indices into joints of the chain roots. */
  readonly chains: readonly number[];
  /** Nodes whose world matrices the caller provides; driverMatrices[16*i..16*i+15] is drivers[i]. */
  readonly drivers: readonly Driver[];
  /** Collision shapes (loadRig's colliders option, or the VRM's own). Every joint collides with the ones it lists. */
  readonly colliders: readonly Collider[];
  /** Everything that was clamped, replaced or ignored while loading. */
  readonly warnings: readonly Warning[];
  readonly disposed: boolean;
  /** A simulation state for one avatar. @throws SpringBonesError 'disposed' after dispose() */
  createInstance(options?: InstanceOptions): Instance;
  /** Releases the rig. Its instances keep working until they are disposed. Idempotent. */
  dispose(): void;
}

/** One avatar's simulation state. */
/**
 * A wind (docs/semantics.md, "Wind"): a pull on every joint's tail like gravityPower x gravityDir,
 * with gusts that are a function of the seed and the instance's simulated time, so the same seed
 * gives the same motion.
 */
export interface WindOptions {
  /** World direction, 3 finite numbers of any size (made unit); not all zero unless strength is 0. */
  direction: readonly [number, number, number] | Float32Array | Float64Array;
  /** World units per second, as gravityPower, in [0, 10]. */
  strength: number;
  /** Gusts per second, in [0, 10]; the pull varies smoothly between 50% and 100% of strength. Default 0: steady. */
  gustFrequency?: number;
  /** An integer in [0, 2^32 - 1] choosing the gust sequence. Default 0. */
  seed?: number;
}

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
  /**
   * Joint world matrices after the last step, column-major 4x4, 16 floats per rig.joints entry
   * (for drawing chains or writing bone.matrixWorld). Computed on read: one call into WebAssembly.
   */
  readonly worldMatrices: Float32Array;
  readonly disposed: boolean;
  /**
   * Advances by a frame of dt seconds: fixed steps of 1/stepHz, at most maxSubsteps per frame.
   * dt <= 0 does nothing. The only call per frame that crosses into WebAssembly; allocates nothing.
   * A dt over 1 s (milliseconds given for seconds: step(16)) prints one console warning per module.
   * @throws TypeError if dt is not a number, RangeError if it is NaN or infinite
   */
  step(dt: number): void;
  /**
   * Fixed steps (substeps) the last frame ran, by this instance's step() or its scene's: 0 when
   * dt did not reach the next step, was <= 0, or a scene's budget held the instance;
   * maxSubsteps when the frame was longer than that many steps (the rest of it is dropped).
   */
  readonly lastSteps: number;
  /**
   * Forgets the motion (avatar swap): the next step starts at rest under the drivers. A teleport
   * needs no reset: it is a jump.
   */
  reset(): void;
  /**
   * Treats the driver change before the next step as a discontinuity (an animation starting, a
   * cut, a snap turn below the thresholds): each chain's tails move with the jump of the driver
   * the chain hangs from (what its pose changed beyond its last motion continued), so the chain
   * keeps its shape and motion relative to the avatar and the jump adds no velocity. Drivers
   * moving beyond jumpDistance / jumpAngle per step are jumps without this call.
   */
  jump(): void;
  /**
   * Wind on this instance from its next step on; null for none. Overrides its scenes' wind until
   * a scene's setWind is called again. TypeError / RangeError for a bad argument.
   */
  setWind(wind: WindOptions | null): void;
  /**
   * Takes over the motion of `previous`, an instance of another rig read from the same skeleton
   * (the rig rebuilt with edited parameters or chains), so the edit neither pops nor restarts the
   * chains. Call it after writing this instance's driverMatrices with the pose `previous` last
   * stepped under, before this instance's first step. Joints of both rigs (same node and tail)
   * keep their tail state (position and velocity) and rotation; joints new to this rig start at
   * rest; the step clock and wind carry over. Nothing happens when `previous` never stepped.
   * TypeError for a value that is not an Instance of this module; SpringBonesError 'disposed'
   * when either is disposed of.
   */
  carryFrom(previous: Instance): void;
  /** Discontinuities carried so far (jump() calls that reached a step, and detected jumps). */
  readonly jumps: number;
  /**
   * Runs the springs to rest under the current driverMatrices without rendering (thumbnails,
   * turntables, emote starts): every tail is put where its stiffness, gravity and wind balance,
   * then stepped with no velocity (for the colliders) until no joint turns by more than 1e-5 rad
   * in a step, at most seconds x stepHz steps. Deterministic:
   * the same pose gives the same result. The next step starts there with no velocity and the
   * drivers as they are. Returns the steps it ran.
   * @param seconds default 2, in [0, 60]
   * @throws RangeError for seconds outside [0, 60] or NaN, TypeError for a non-number
   */
  settle(seconds?: number): number;
  /**
   * Holds rig.joints[joint]'s tail toward a world point from the next step on: the joints from its
   * chain root down to it turn toward the point as far as the chain reaches, colliders still
   * holding; the joints below swing. Call it every frame with a moving point (a drag).
   * @throws RangeError for a disposed instance, a joint out of range or a point not finite in
   *   float32 (it crosses as float32: [1e39, 0, 0] is refused, naming point[0]); TypeError for a
   *   non-number joint or a point that is not 3 numbers
   */
  grab(joint: number, point: readonly number[] | Float32Array | Float64Array): void;
  /**
   * Lets go: the chain swings back from where and how fast it was moving, with no jolt.
   * @throws RangeError for a disposed instance
   */
  release(): void;
  /** The joint grab() holds, -1 for none. */
  readonly grabbedJoint: number;
  /**
   * Sets the inertia (InstanceOptions.inertia) of chain `chain` (an index into rig.chains), or of
   * every chain when omitted, from the next step on.
   * @throws RangeError for a value outside [0, 1] or a chain out of range
   */
  setInertia(value: number, chain?: number): void;
  /**
   * Replaces this instance's colliders (its rig's included) from its next step on, for whichever
   * integrator runs it; every joint then collides with all of them, with the rig's hitRadius.
   * `colliders` takes what LoadOptions.colliders takes, by the same rules and errors (paths such as
   * `setColliders: colliders[2].radius`); null or [] for none. A collider's `node` that names one
   * of rig.drivers follows that driver; any other name becomes a frame (frameNames), whose world
   * matrix the page writes each frame into frameMatrices: another wearable's node, a hat, a hand.
   * The rig's own colliders given again move the tails exactly as before. An instance whose
   * colliders differ from its rig's in number, kind or which joints meet them steps on the general
   * path rather than the lanes (the same motion rules). docs/semantics.md, "Colliders at run time".
   * @returns the warnings of the shapes (`collider-invalid`, `collider-on-spring-bone`,
   *   `body-collider-skipped`), as rig.warnings has them for loadRig's
   * @throws TypeError / RangeError for a bad collider or option, SpringBonesError 'disposed'
   */
  setColliders(colliders: readonly ColliderOptions[] | ColliderPreset | null, options?: SetCollidersOptions): readonly Warning[];
  /** The frames setColliders made, in frameMatrices' order: collider nodes that are no rig driver. */
  readonly frameNames: readonly string[];
  /**
   * World matrices of the frames (column-major 4x4, 16 floats per frameNames entry, world space as
   * driverMatrices), written by the caller before step(); each holds for every substep of the frame
   * (not interpolated). A matrix with an entry that is not a number within +-1e12 is ignored (the
   * frame keeps its last good one); until written, a frame is its avatarBones rest matrix, else the
   * GLB node's of its name, else the identity. A new array after each setColliders; same view rules
   * as driverMatrices.
   */
  readonly frameMatrices: Float32Array;
  /**
   * Frees the instance, first removing it from every scene it is in. Idempotent; any other use
   * afterwards throws SpringBonesError 'disposed'.
   */
  dispose(): void;
}

/** Many instances stepped in one call, optionally only the ones nearest to the viewer. */
export interface Scene {
  /** Number of instances in it. */
  readonly size: number;
  /**
   * x, y, z per instance in slot order, written by the caller (e.g. each avatar's position) for
   * the budget. A view into WebAssembly memory, replaced after memory growth and by add()/remove():
   * read the property rather than keeping the array.
   */
  readonly positions: Float32Array;
  readonly disposed: boolean;
  /** Adds an instance of the same module; returns its slot. Adding it again returns the same slot. */
  add(instance: Instance): number;
  /** Removes it (later slots shift down); nothing happens if it is not in the scene. */
  remove(instance: Instance): void;
  /** The instance's slot in positions, -1 if it is not in the scene. */
  slotOf(instance: Instance): number;
  /**
   * Simulate only the maxActive instances nearest to the viewer; the others hold their last pose
   * and restart from rest when they come back. maxActive null or Infinity: no budget (the default).
   * @throws RangeError for a negative or fractional maxActive, or coordinates not finite as float32
   */
  setBudget(maxActive: number | null, viewerX?: number, viewerY?: number, viewerZ?: number): void;
  /** Wind on every instance in the scene and on each one added later; null for none. */
  setWind(wind: WindOptions | null): void;
  /**
   * Steps every (budgeted) instance by dt seconds, as instance.step does, in one call: the
   * instances of one rig go through each step together (one SIMD kernel pass over all their
   * chains), with the same results, bit for bit, as stepping them one by one. Allocates nothing.
   */
  step(dt: number): void;
  /** Whether the instance was simulated by the last step. */
  isActive(instance: Instance): boolean;
  /**
   * isActive for every instance at once: 1 or 0 per slot in slot order, as the last step left
   * them (1 before any step). Read-only; a view replaced like positions: read the property.
   */
  readonly active: Uint8Array;
  /** Frees the scene (not its instances). Idempotent; other use afterwards throws 'disposed'. */
  dispose(): void;
}
