// Which nodes to recompute each frame so that the drivers' world matrices are this frame's when
// the simulation reads them, in the scene's before-render.
//
// There Babylon has applied the frame's animations to the nodes' local transforms but not yet
// recomputed world matrices, and its render id is still the previous frame's, so a world matrix
// cached under that id is last frame's. `computeWorldMatrix(true)` recomputes a node; whether
// that also forces its ancestors depends on the version: the current one does (each ancestor is
// forced in turn), Babylon 4.2 does not (it takes the parent's matrix from that cache). So this is
// found out once, by watching whether forcing a node recomputes its grandparent (forcingReachesAncestors
// says why not its parent): if it does, forcing each driver is enough. If not (4.2), every ancestor of every driver is brought up to date
// without forcing, each once, parents first: 4.2 recomputes a node whose transform or whose
// ancestors changed and keeps the others, whose cached matrices are then right. Forcing them all
// instead would recompute the loader's `__root__` mesh too, which in 4.2 allocates.

/**
 * Whether computeWorldMatrix(true) on `node` recomputes its ancestors too (for unchanged ones).
 * Watched on the grandparent: 4.2's forced node recomputes its parent, unforced (which a glTF
 * node, whose rotation quaternion 4.2 never marks clean, does each time), but that parent takes
 * the grandparent's cached matrix, so the parent alone would pass for a version that forces up.
 */
function forcingReachesAncestors(node) {
  const watched = node.parent?.parent ?? node.parent;
  const observable = watched?.onAfterWorldMatrixUpdateObservable;
  if (!observable) return true;  // no parent to bring up to date
  node.computeWorldMatrix(true);  // everything above is now in step: only forcing recomputes it
  let reached = false;
  const observer = observable.add(() => {
    reached = true;
  });
  node.computeWorldMatrix(true);
  observable.remove(observer);
  return reached;
}

/**
 * { nodes, force }: call computeWorldMatrix(force) on each of `nodes` each frame, in order, for
 * these drivers (null entries skipped); after that, every driver's getWorldMatrix() is this frame's.
 */
export function nodesToRecompute(drivers) {
  const present = [...new Set(drivers.filter((d) => d !== null))];
  const probe = present.find((d) => d.parent);
  if (!probe || forcingReachesAncestors(probe)) return { nodes: present, force: true };
  const ordered = [];
  const seen = new Set();
  for (const driver of present) {
    const chain = [];
    for (let node = driver; node && !seen.has(node); node = node.parent) chain.push(node);
    for (let i = chain.length - 1; i >= 0; i--) {
      seen.add(chain[i]);
      ordered.push(chain[i]);
    }
  }
  return { nodes: ordered, force: false };
}
