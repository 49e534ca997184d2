// An instance: the simulation state of one avatar wearing a rig, with typed-array views over its
// buffers in WebAssembly memory (made again when memory growth detaches them).

import { checkDt, checkFloat32, checkInteger, checkRange, checkVec3, windArguments } from './arguments.js';
import { deepFreeze } from './deep_freeze.js';
import { disposedError, takeError } from './errors.js';
import { kLongFrameSeconds, warnLongFrame } from './long_frame.js';
import { colliderChange } from './rig_options.js';
import { takeTyped } from './typed_output.js';
import { isStale, withBytes } from './wasm_memory.js';

/**
 * Accessors into an instance's private fields for the scene (scene.js), which reads its module
 * and handle and joins its scene list: installed by Instance's static block.
 */
export let instanceInternals;

export class Instance {
  #m;
  #handle;
  #limits;
  #driverPtr;
  #rotationsPtr;
  #worldPtr;
  #driverFloats;
  #rotationFloats;
  #drivers;
  #rotations;
  #world;
  #framePtr = 0;  // setColliders' frames: where their matrices are, how many floats, the view
  #frameFloats = 0;
  #frames = new Float32Array(0);
  #frameNames = Object.freeze([]);
  #scenes = new Map();  // the scenes this instance is in -> how each forgets it, called on dispose
  #chainCount;  // () => the rig's chain count

  static {
    instanceInternals = {
      module: (instance) => instance.#m,
      handle: (instance) => instance.#handle,
      scenes: (instance) => instance.#scenes,
    };
  }

  constructor(m, handle, limits, chainCount) {
    this.#m = m;
    this.#handle = handle;
    this.#limits = limits;
    this.#chainCount = chainCount;
    this.#driverPtr = m.driverMatricesPtr(handle);
    this.#rotationsPtr = m.rotationsPtr(handle);
    this.#worldPtr = m.worldMatricesPtr(handle);
    this.#driverFloats = 16 * m.driverCount(handle);
    this.#rotationFloats = 4 * m.jointCount(handle);
    this.#drivers = this.#view(this.#driverPtr, this.#driverFloats);
    this.#rotations = this.#view(this.#rotationsPtr, this.#rotationFloats);
    this.#world = this.#view(this.#worldPtr, 4 * this.#rotationFloats);
    Object.freeze(this);
  }

  get disposed() {
    return this.#handle === 0;
  }

  /** Driver world matrices (column-major 4x4, 16 floats per rig.drivers entry), written before step(). */
  get driverMatrices() {
    this.#live();
    if (isStale(this.#m, this.#drivers, this.#driverFloats)) {
      this.#drivers = this.#view(this.#driverPtr, this.#driverFloats);
    }
    return this.#drivers;
  }

  /** Local rotations (x, y, z, w), 4 floats per rig.joints entry, current after step(). */
  get rotations() {
    this.#live();
    if (isStale(this.#m, this.#rotations, this.#rotationFloats)) {
      this.#rotations = this.#view(this.#rotationsPtr, this.#rotationFloats);
    }
    return this.#rotations;
  }

  /**
   * Joint world matrices (column-major 4x4, 16 floats per rig.joints entry) after the last step.
   * The core writes them on request, so each read of this property is one call into WebAssembly.
   */
  get worldMatrices() {
    this.#m.worldMatricesPtr(this.#live());  // fills the buffer; its address never changes
    if (isStale(this.#m, this.#world, 4 * this.#rotationFloats)) {
      this.#world = this.#view(this.#worldPtr, 4 * this.#rotationFloats);
    }
    return this.#world;
  }

  /** Advances by a frame of dt seconds (fixed substeps inside). dt <= 0 does nothing. */
  step(dt) {
    this.#m.step(this.#live(), checkDt(dt));
    if (dt > kLongFrameSeconds) warnLongFrame(this.#m, 'step', dt);
  }

  /**
   * Fixed steps the last frame ran (its step, or its scene's): 0 when dt did not reach the next
   * step or a scene's budget held the instance; maxSubsteps when the frame was longer.
   */
  get lastSteps() {
    return this.#m.lastSteps(this.#live());
  }

  /** Forgets the motion (avatar swaps): the next step starts at rest. */
  reset() {
    this.#m.reset(this.#live());
  }

  /**
   * Treats the driver change before the next step as a discontinuity (an animation starting, a
   * cut): the chains are carried across it with the drivers they hang from, keeping their shape
   * and motion, with no whip. Teleports and snap turns beyond jumpDistance / jumpAngle are
   * noticed without it.
   */
  jump() {
    this.#m.jump(this.#live());
  }

  /**
   * Wind on this instance from its next step on: {direction: [x, y, z] (world, normalized),
   * strength (world units per second, like gravityPower), gustFrequency? (gusts per second, 0:
   * steady), seed? (an integer; the same seed, the same gusts)}; null for none. Overrides its
   * scenes' wind until a scene's is set again.
   */
  setWind(wind) {
    this.#m.setWind(this.#live(), ...windArguments('setWind', wind, this.#limits));
  }

  /**
   * Takes over the motion of `previous`, an instance of another rig of the same skeleton (the rig
   * rebuilt with edited parameters), with no pop: call it after writing this instance's
   * driverMatrices with the pose `previous` last stepped under, before this instance's first step.
   * Joints both rigs have keep their tail state (position and velocity) and rotation, new joints
   * start at rest; the step clock and wind carry over. `previous` is left as it is.
   */
  carryFrom(previous) {
    if (!(previous instanceof Instance)) throw new TypeError('carryFrom: previous must be an instance from rig.createInstance()');
    if (previous.#m !== this.#m) throw new TypeError('carryFrom: previous belongs to another springbones module');
    if (previous.#handle === 0) throw disposedError('instance');
    this.#m.carryFrom(this.#live(), previous.#handle);
  }

  /** Discontinuities carried so far (jump() calls that reached a step, and detected jumps). */
  get jumps() {
    return this.#m.jumps(this.#live());
  }

  /**
   * Runs the springs to rest under the driver matrices as they are, without a frame (thumbnails,
   * turntables, emote starts): at most `seconds` x stepHz steps, fewer once no joint turns any
   * more. Deterministic; returns the steps it ran. The next step starts from there at rest.
   */
  settle(seconds = this.#limits.settleSeconds) {
    const handle = this.#live();
    checkRange('settle: seconds', seconds, 0, this.#limits.maxSettleSeconds);
    return this.#m.settle(handle, seconds);
  }

  /**
   * Holds rig.joints[joint]'s tail toward a world point ([x, y, z]) from the next step on, as far
   * as its chain reaches, colliders still holding; call it every frame with the moving point.
   * RangeError for a disposed instance, a joint out of range or a point that is not finite in
   * float32 (it crosses as float32, where [1e39, 0, 0] would be infinite and the core would
   * ignore it).
   */
  grab(joint, point) {
    const handle = this.#grabHandle('grab');
    checkInteger('grab: joint', joint, 0, this.#rotationFloats / 4 - 1);
    const [x, y, z] = checkVec3('grab: point', point);
    checkFloat32('grab: point[0]', x);
    checkFloat32('grab: point[1]', y);
    checkFloat32('grab: point[2]', z);
    this.#m.grab(handle, joint, x, y, z);
  }

  /** Lets go of the grabbed joint: the chain swings back from where it is. RangeError once disposed. */
  release() {
    this.#m.release(this.#grabHandle('release'));
  }

  /** The joint grab() holds, or -1. */
  get grabbedJoint() {
    return this.#m.grabbedJoint(this.#live());
  }

  /**
   * How much of the motion of the driver a chain hangs from it feels, in [0, 1]: 1 all of it (the
   * default), 0 none (hair calm in a vehicle). `chain`: an index into rig.chains; omitted, every
   * chain. From the next step on.
   */
  setInertia(value, chain) {
    const handle = this.#live();
    checkRange('setInertia: value', value, 0, 1);
    let index = -1;
    if (chain !== undefined) index = checkInteger('setInertia: chain', chain, 0, this.#chainCount() - 1);
    this.#m.setInertia(handle, value, index);
  }

  /**
   * Replaces this instance's colliders (its rig's included) from its next step on: `colliders` as
   * loadRig's option takes them (an array of colliders, or 'dcl-body'), null or [] for none;
   * `options` {avatarBones?, scale?, omit?}: the avatar's bones for 'dcl-body', and its radii
   * times `scale`, its shapes named in `omit` left out. Every joint then collides with all of
   * them. A collider's node is a rig driver of that name, or else a frame the page writes each
   * frame (frameNames, frameMatrices). Returns the warnings of the shapes (the rig's codes:
   * collider-invalid, collider-on-spring-bone, body-collider-skipped).
   */
  setColliders(colliders, options) {
    const handle = this.#live();
    const typed = colliderChange('setColliders', colliders, options, this.#limits);
    const m = this.#m;
    const length = withBytes(m, typed, (ptr, size) => m.setColliders(handle, ptr, size));
    if (length === 0) throw takeError(m);
    const { frames, warnings } = takeTyped(m, length);
    this.#frameNames = deepFreeze(frames);
    this.#framePtr = m.frameMatricesPtr(handle);
    this.#frameFloats = 16 * frames.length;
    this.#frames = this.#view(this.#framePtr, this.#frameFloats);
    return deepFreeze(warnings);
  }

  /** The frames setColliders made (collider nodes that are no driver of the rig), in frameMatrices' order. */
  get frameNames() {
    this.#live();
    return this.#frameNames;
  }

  /**
   * The frames' world matrices (column-major 4x4, 16 floats per frameNames entry), written before
   * step() as driverMatrices are: what the colliders on each frame follow. A new array after each
   * setColliders.
   */
  get frameMatrices() {
    this.#live();
    if (isStale(this.#m, this.#frames, this.#frameFloats)) this.#frames = this.#view(this.#framePtr, this.#frameFloats);
    return this.#frames;
  }

  /**
   * Frees the instance, first taking it out of every scene it is in; its views must not be used
   * afterwards. Calling it again does nothing.
   */
  dispose() {
    if (this.#handle === 0) return;
    for (const forget of this.#scenes.values()) forget(this);
    this.#scenes.clear();
    this.#m.disposeInstance(this.#handle);  // also removes it from the scenes on the WASM side
    this.#handle = 0;
  }

  // The handle, checked: every method but dispose() throws once the instance is disposed of.
  #live() {
    if (this.#handle === 0) throw disposedError('instance');
    return this.#handle;
  }

  // grab and release take a disposed instance for a bad argument, as an out-of-range joint: a
  // pointer handler keeps calling them with whatever instance it last picked.
  #grabHandle(where) {
    if (this.#handle === 0) throw new RangeError(`${where}: the instance has been disposed`);
    return this.#handle;
  }

  #view(ptr, length) {
    return new Float32Array(this.#m.HEAPF32.buffer, ptr, length);
  }
}

