// Why a worn wearable's hair does not move: the diagnostics both adapters give
// (docs/diagnostics.md has each code's message and fix).

export type DiagnosticCode =
  | 'module-failed'          // the springbones module did not load
  | 'rig-failed'             // loadRig refused the metadata or options
  | 'springbones-missing'    // no springBones, though the GLB has spring-bone nodes
  | 'models-missing'         // the core's: springBones has no models
  | 'model-not-found'        // the core's: no models entry for this GLB's hash
  | 'springbones-ambiguous'  // Babylon: the whole springBones with several models, none under the item id
  | 'entry-not-matched'      // none of the entry's names is a node of this GLB
  | 'no-chain-root'          // no entry has isRoot: true
  | 'unrooted-bones'         // some bones with entries have no isRoot and no root above them
  | 'no-chains'              // three.js attachWearable with a rig alone: no chain, spring-bone nodes in the GLB
  | 'bone-not-matched'       // avatar bones the chains hang from (or colliders sit on) were not found
  | 'unknown-item'           // Babylon: a call named an id not registered
  | 'node-not-found'         // three.js: a joint or driver without an object
  | 'collider-invalid'       // setColliders: the core left a shape out (size beyond 1e6, bad plane)
  | 'collider-on-spring-bone' // setColliders: a collider on a simulated joint
  | 'body-collider-skipped'  // setColliders: 'dcl-body' shapes whose bones are missing
  | 'collider-not-followed'; // setColliders: a collider's node names nothing in the scene

/** One reason the hair stays still, with the fix. */
export interface Diagnostic {
  readonly code: DiagnosticCode;
  /** What is wrong and what it does to the hair. */
  readonly message: string;
  /** What to change so that the spring bones move. */
  readonly fix: string;
  /** JSON pointer into springBones (or the error's path) when the reason is in the metadata, else ''. */
  readonly path: string;
}
