// The numbers of the preview's readout: the springs' cost per frame as the median over the last
// second of frames (an average over a long ring kept the first, compiling frames and frames of
// another wearable in the number for many seconds), and how many fixed steps the last frame took.

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

/**
 * The fixed steps an instance takes per frame, counted as the core counts them (an accumulator of
 * frame time; a step wherever it crosses a multiple of 1/stepHz, with the same tolerance; at most
 * maxSubsteps, the rest of a longer frame dropped), because the JavaScript API does not report
 * them. Kept in step with the instances it mirrors: reset() whenever they are created or reset.
 */
export class SubstepCounter {
  constructor({ stepHz, maxSubsteps }) {
    this.stepSeconds = 1 / stepHz;
    this.maxSubsteps = maxSubsteps;
    this.accumulator = 0;
  }

  reset() {
    this.accumulator = 0;
  }

  /** The steps of a frame of dt seconds (0 for dt <= 0, as the core skips such frames). */
  frame(dt) {
    if (!(dt > 0) || !Number.isFinite(dt)) return 0;
    const h = this.stepSeconds;
    this.accumulator += dt;
    const crossed = Math.floor((this.accumulator + h * 1e-6) / h);
    const dropped = crossed > this.maxSubsteps;
    const steps = dropped ? this.maxSubsteps : crossed;
    this.accumulator = dropped ? 0 : Math.max(0, this.accumulator - steps * h);
    return steps;
  }
}
