// A scene: many instances stepped in one call, optionally only the ones nearest the viewer.

import { checkDt, checkFloat32, checkInteger, windArguments } from './arguments.js';
import { call, disposedError, takeError } from './errors.js';
import { Instance, instanceInternals } from './instance.js';
import { kLongFrameSeconds, warnLongFrame } from './long_frame.js';
import { isStale } from './wasm_memory.js';

export class Scene {
  #m;
  #handle;
  #limits;
  #members = [];  // instances in slot order, as the core holds them
  #positions;
  #active;

  constructor(m, handle, limits) {
    this.#m = m;
    this.#handle = handle;
    this.#limits = limits;
    this.#refresh();
    Object.freeze(this);
  }

  get disposed() {
    return this.#handle === 0;
  }

  /** Number of instances in the scene. */
  get size() {
    return this.#members.length;
  }

  /**
   * x, y, z per instance in slot order (the order of add(); slots shift down on remove), written
   * by the caller, e.g. each avatar's root position; used by the budget. Same view rules as
   * instance.driverMatrices, and the view is also replaced by add() and remove().
   */
  get positions() {
    this.#live();
    if (isStale(this.#m, this.#positions, 3 * this.#members.length)) this.#refresh();
    return this.#positions;
  }

  /**
   * isActive for every instance at once: 1 or 0 per slot, in slot order, as the last step left
   * them (1 before any step). For pages that handle many avatars a frame (the three.js group
   * writes only the active ones' bones). Read-only; same view rules as positions.
   */
  get active() {
    this.#live();
    if (isStale(this.#m, this.#active, this.#members.length)) this.#refresh();
    return this.#active;
  }

  /** Adds an instance (of this module) and returns its slot; adding it again returns the same slot. */
  add(instance) {
    const handle = this.#instanceHandle('add', instance);
    const existing = this.#members.indexOf(instance);
    if (existing >= 0) return existing;
    const m = this.#m;
    const slot = call(() => m.sceneAdd(this.#handle, handle));
    if (slot === 0) throw takeError(m);
    this.#members.push(instance);
    instanceInternals.scenes(instance).set(this, (gone) => this.#forget(gone));
    this.#refresh();
    return slot - 1;
  }

  /** Takes an instance out (its later slots shift down). Not in the scene: nothing happens. */
  remove(instance) {
    const handle = this.#instanceHandle('remove', instance);
    if (!this.#members.includes(instance)) return;
    this.#m.sceneRemove(this.#handle, handle);
    instanceInternals.scenes(instance).delete(this);
    this.#forget(instance);
  }

  /** The slot of an instance in positions, or -1 when it is not in the scene. */
  slotOf(instance) {
    this.#live();
    return this.#members.indexOf(instance);
  }

  /**
   * Simulate only the maxActive instances nearest to the viewer (the others hold their last pose
   * and restart from rest when they come back). maxActive null or Infinity: no budget.
   */
  setBudget(maxActive, viewerX = 0, viewerY = 0, viewerZ = 0) {
    const handle = this.#live();
    let max = -1;
    if (maxActive !== null && maxActive !== Infinity) {
      max = checkInteger('setBudget: maxActive', maxActive, 0, 0x7fffffff);
    }
    // Checked one by one, not through an array of pairs: pages call this every frame. They cross
    // as float32, where a larger value is infinite and the core would ignore the viewer.
    checkFloat32('setBudget: viewerX', viewerX);
    checkFloat32('setBudget: viewerY', viewerY);
    checkFloat32('setBudget: viewerZ', viewerZ);
    this.#m.sceneSetBudget(handle, max, viewerX, viewerY, viewerZ);
  }

  /**
   * Wind on every instance of the scene, and on each one added later (instance.setWind's
   * argument; null for none). An instance's own setWind afterwards overrides it for that one.
   */
  setWind(wind) {
    this.#m.sceneSetWind(this.#live(), ...windArguments('setWind', wind, this.#limits));
  }

  /** Steps every instance (or the budget's nearest) by dt seconds, in one call into WebAssembly. */
  step(dt) {
    this.#m.sceneStep(this.#live(), checkDt(dt));
    if (dt > kLongFrameSeconds) warnLongFrame(this.#m, 'scene.step', dt);
  }

  /** Whether the instance was simulated by the last step (false when it is not in the scene). */
  isActive(instance) {
    this.#live();
    const slot = this.#members.indexOf(instance);
    return slot >= 0 && this.#m.sceneIsActive(this.#handle, slot);
  }

  /** Frees the scene; its instances are not disposed of. Calling it again does nothing. */
  dispose() {
    if (this.#handle === 0) return;
    for (const instance of this.#members) instanceInternals.scenes(instance).delete(this);
    this.#members = [];
    this.#m.disposeScene(this.#handle);
    this.#handle = 0;
  }

  // The handle, checked: every method but dispose() throws once the scene is disposed of.
  #live() {
    if (this.#handle === 0) throw disposedError('scene');
    return this.#handle;
  }

  #instanceHandle(where, instance) {
    this.#live();
    if (!(instance instanceof Instance)) throw new TypeError(`${where}: expected an instance from rig.createInstance()`);
    if (instanceInternals.module(instance) !== this.#m) {
      throw new TypeError(`${where}: the instance belongs to another springbones module`);
    }
    const handle = instanceInternals.handle(instance);
    if (handle === 0) throw disposedError('instance');
    return handle;
  }

  // The core dropped the instance (remove, or its dispose): mirror the slot shift.
  #forget(instance) {
    const slot = this.#members.indexOf(instance);
    if (slot >= 0) this.#members.splice(slot, 1);
    this.#refresh();
  }

  // The views, made again: after add() and remove(), and when memory growth detached them.
  #refresh() {
    const m = this.#m;
    this.#positions = new Float32Array(m.HEAPF32.buffer, m.scenePositionsPtr(this.#handle), 3 * this.#members.length);
    this.#active = new Uint8Array(m.HEAPU8.buffer, m.sceneActivePtr(this.#handle), this.#members.length);
  }
}

