// Notices an AnimationMixer action starting, for the adapter to call instance.jump(): an animation
// that starts (an emote, a cut to another clip) moves the avatar's bones farther in one frame than
// any motion does, and read as velocity the springs would whip.
//
// AnimationMixer announces only 'loop' and 'finished', so the watch compares the mixer's active
// actions with the ones it saw last time. It reads the mixer's `_actions` / `_nActiveActions`
// (the list stats.actions.inUse counts, the active ones first), which every three.js release the
// package supports (peerDependencies) keeps, and each action's effective weight. Allocation-free
// per frame.

export class AnimationStartWatch {
  #seen; #weighted; #seenCount;

  /** @param {import('three').AnimationMixer} mixer */
  constructor(mixer) {
    if (!Array.isArray(mixer?._actions) || typeof mixer?._nActiveActions !== 'number') {
      throw new TypeError('AnimationStartWatch: expected a three.js AnimationMixer');
    }
    this.mixer = mixer;
    this.#seen = [];  // the actions active at the last look
    this.#weighted = [];  // and whether each had a weight
    this.#seenCount = 0;
    this.started();  // what runs now is not a start
  }

  /**
   * Whether an action started since the last call: became active in the mixer, or, active but
   * weightless (faded out, disabled), got a weight again (action.reset().play() on it).
   */
  started() {
    const actions = this.mixer._actions;
    const active = this.mixer._nActiveActions;
    const seen = this.#seen;
    const weighted = this.#weighted;
    let startedOne = false;
    for (let i = 0; i < active; i++) {
      const action = actions[i];
      const hasWeight = action.getEffectiveWeight() > 0;
      let before = false;  // active with a weight at the last look
      for (let k = 0; k < this.#seenCount; k++) {
        if (seen[k] === action) {
          before = weighted[k];
          break;
        }
      }
      if (hasWeight && !before) startedOne = true;
    }
    for (let i = 0; i < active; i++) {  // grow only when more are active than ever
      seen[i] = actions[i];
      weighted[i] = actions[i].getEffectiveWeight() > 0;
    }
    this.#seenCount = active;
    return startedOne;
  }
}
