// The bookkeeping of the per-frame copies, for both adapters' loops (the loops themselves, which
// read the engine's matrices and write its rotations, stay in the engine files): the members'
// instances, how many drivers and joints each has, and each instance's views, kept from frame to
// frame. instance.driverMatrices / rotations are getters that check for memory growth on every
// call, so a view is fetched again only when its instance is disposed of (the getter then throws
// the API's 'disposed' error: nothing is written into freed memory) or its length is not the
// expected one (growing WebAssembly memory detaches the old buffer; a detached view has length 0).
// Allocation-free per frame.

const kNoView = new Float32Array(0);

export class FrameCopyLists {
  constructor() {
    this.setCounts([], [], []);
  }

  /**
   * The members' instances and their driver, joint and frame counts (frames: the objects their
   * setColliders colliders follow; none by default); call whenever they change.
   */
  setCounts(instances, driverCounts, jointCounts, frameCounts = instances.map(() => 0)) {
    this.instances = instances;
    this.driverCounts = driverCounts;
    this.jointCounts = jointCounts;
    this.frameCounts = frameCounts;
    this.driverViews = instances.map(() => kNoView);  // fetched on first use
    this.rotationViews = instances.map(() => kNoView);
    this.frameViews = instances.map(() => kNoView);
  }

  /** Member i's frameMatrices, 16 floats per frame (a new array after each setColliders: call setCounts). */
  frameView(i) {
    const view = this.frameViews[i];
    if (!this.instances[i].disposed && view.length === 16 * this.frameCounts[i]) return view;
    return (this.frameViews[i] = this.instances[i].frameMatrices);
  }

  /** Member i's driverMatrices, 16 floats per driver. */
  driverView(i) {
    const view = this.driverViews[i];
    if (!this.instances[i].disposed && view.length === 16 * this.driverCounts[i]) return view;
    return (this.driverViews[i] = this.instances[i].driverMatrices);
  }

  /** Member i's rotations, 4 floats per joint. */
  rotationView(i) {
    const view = this.rotationViews[i];
    if (!this.instances[i].disposed && view.length === 4 * this.jointCounts[i]) return view;
    return (this.rotationViews[i] = this.instances[i].rotations);
  }
}
