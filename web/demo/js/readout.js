// The numbers of the preview's readout: the springs' cost per frame as the median over the last
// second of frames (an average over a long ring kept the first, compiling frames and frames of
// another wearable in the number for many seconds). How many fixed steps the last frame took comes
// from the core (instance.lastSteps).

/**
 * The last `windowMs` of frame samples: { at (performance.now() at the frame's end), ms, joints,
 * integrator }. A bounded ring: a test advancing thousands of frames at once keeps the newest.
 */
export class RecentFrames {
  constructor(windowMs = 1000, capacity = 2048) {
    this.windowMs = windowMs;
    this.ring = new Array(capacity);
    this.count = 0;  // samples written since the last clear
  }

  add(at, ms, joints, integrator) {
    const slot = this.count++ % this.ring.length;
    const sample = this.ring[slot] ?? (this.ring[slot] = { at: 0, ms: 0, joints: 0, integrator: '' });
    sample.at = at;
    sample.ms = ms;
    sample.joints = joints;
    sample.integrator = integrator;
  }

  /** How many samples the ring holds, however old. */
  get held() {
    return Math.min(this.count, this.ring.length);
  }

  /** Forgets every sample: what follows is another wearable, rig or integrator. */
  clear() {
    this.count = 0;
  }

  /** Copies of the samples of the last windowMs before `now`, oldest first. */
  samples(now = performance.now()) {
    const out = [];
    for (let i = this.count - this.held; i < this.count; i++) {
      const s = this.ring[i % this.ring.length];
      if (now - s.at <= this.windowMs) out.push({ ...s });
    }
    return out;
  }

  /** The median ms of samples(now) (the upper one of an even count); NaN when there are none. */
  medianMs(now = performance.now()) {
    const ms = this.samples(now).map((s) => s.ms).sort((a, b) => a - b);
    return ms.length ? ms[ms.length >> 1] : NaN;
  }
}
