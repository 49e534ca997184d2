// Frozen plain data: what the API hands out of the core's JSON text (the rig's description, the
// limits) cannot be changed by a caller, so every reader sees what the core said.

export function deepFreeze(value) {
  if (value !== null && typeof value === 'object') {
    for (const key of Object.keys(value)) deepFreeze(value[key]);
    Object.freeze(value);
  }
  return value;
}
