// Counting the collisions of @pixiv/three-vrm-springbone's colliders, so that a run comparing
// with it is known to exercise them.

/**
 * From now on every collision a collider of the manager reports (a negative distance) adds one to
 * the returned object, under keyOf(collider); each key starts at 0.
 */
export function countCollisions(manager, keyOf) {
  const collisions = {};
  for (const collider of manager.colliders) {
    const shape = collider.shape;
    const key = keyOf(collider);
    collisions[key] ??= 0;
    const original = shape.calculateCollision.bind(shape);
    shape.calculateCollision = (...args) => {
      const d = original(...args);
      if (d < 0) collisions[key]++;
      return d;
    };
  }
  return collisions;
}
