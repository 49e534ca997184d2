// A loaded rig (sb.loadRig, sb.loadVrm): its description as frozen plain data, and the instances
// made from it.

import { deepFreeze } from './deep_freeze.js';
import { call, disposedError, takeError } from './errors.js';
import { Instance } from './instance.js';
import { instanceOptions } from './rig_options.js';
import { decodeTyped } from './typed_output.js';

export class Rig {
  #m;
  #handle;
  #descriptionBytes;  // the core's typed values (describeRig, springbones/boundary.h) until their first read
  #description;
  #limits;
  #jumps;  // loadRig's jumpDistance / jumpAngle, the default of its instances

  constructor(m, handle, descriptionBytes, limits, jumps = {}) {
    this.#m = m;
    this.#handle = handle;
    this.#descriptionBytes = descriptionBytes;
    this.#limits = limits;
    this.#jumps = jumps;
    Object.freeze(this);
  }

  // The description's fields (springbones.d.ts documents each): frozen plain data, parsed on the
  // first read of any (the per-frame path never needs them) and the same objects on every read
  // after; readable after dispose().
  static {
    for (const key of ['contentHash', 'format', 'nodeCount', 'joints', 'chains', 'drivers', 'colliders', 'warnings']) {
      Object.defineProperty(Rig.prototype, key, { get() { return this.#parsedDescription()[key]; }, configurable: true });
    }
  }

  #parsedDescription() {
    if (this.#description === undefined) {
      this.#description = deepFreeze(decodeTyped(this.#descriptionBytes));
      this.#descriptionBytes = undefined;
    }
    return this.#description;
  }

  get disposed() {
    return this.#handle === 0;
  }

  /** A simulation state for one avatar wearing this item. */
  createInstance(options) {
    if (this.#handle === 0) throw disposedError('rig');
    const { integrator, stepHz, maxSubsteps, xpbdIterations, inertia, jumps } =
      instanceOptions('createInstance', options, this.#limits, this.#jumps);
    const m = this.#m;
    const handle = call(() => m.createInstance(this.#handle, stepHz, maxSubsteps,
                                               integrator === 'xpbd' ? 1 : 0, xpbdIterations));
    if (handle === 0) throw takeError(m);
    if (jumps.jumpDistance !== undefined || jumps.jumpAngle !== undefined) {
      // NaN keeps the core's default for the one not given.
      m.setJumpThresholds(handle, jumps.jumpDistance ?? NaN, jumps.jumpAngle ?? NaN);
    }
    if (inertia !== undefined) m.setInertia(handle, inertia, -1);
    // The chain count for setInertia's check, read from the description only when it is needed.
    return new Instance(m, handle, this.#limits, () => this.chains.length);
  }

  /**
   * Releases the rig. Instances created from it keep working (they share its data) until they
   * are disposed of themselves. Calling dispose() again does nothing.
   */
  dispose() {
    if (this.#handle === 0) return;
    this.#m.disposeRig(this.#handle);
    this.#handle = 0;
  }
}

