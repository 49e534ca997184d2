// The option objects of loadRig and createInstance: their keys and the rules over each, in one
// place (arguments.js says where the other checks live). What crosses for loadRig is typed input
// (typed_value.js) that the core reads again with its own rules (src/boundary/api_values.cpp).

import { checkDenseArray, checkFinite, checkInteger, checkKeys, checkNonEmptyString, checkNonNegative, checkOneOf,
  checkRange, checkVec3, optionsObject, scaledDirection } from './arguments.js';
import { kHashOptions } from './models_entry.js';
import { encodeTyped } from './typed_value.js';

const kJumpOptions = ['jumpDistance', 'jumpAngle'];

/** loadRig's option keys. */
export const kRigOptionKeys = [...kHashOptions, 'colliders', 'avatarBones', 'hitRadius', 'limits', ...kJumpOptions];

/**
 * loadRig's options, checked: `hash` the options that say which models entry applies (checked
 * where they are resolved, models_entry.js), `typed` the rest as the typed input the core reads
 * (no bytes for none), `jumps` the default jumpDistance / jumpAngle of the rig's instances.
 */
export function rigOptions(where, options) {
  const opts = optionsObject(where, options, kRigOptionKeys);
  const { contentHash, entity, bodyShape } = opts;
  return {
    hash: { contentHash, entity, bodyShape },
    typed: typedRigOptions(where, opts),
    jumps: jumpOptions(where, opts, {}),
  };
}

const kIntegrators = ['vrm', 'xpbd'];

/**
 * createInstance's options, checked against the core's limits, as the bindings take them: 0 for
 * stepHz or maxSubsteps leaves them to the core's default for the integrator; `jumps` over the
 * rig's (loadRig's); inertia undefined when not given.
 */
export function instanceOptions(where, options, limits, rigJumps) {
  const opts = optionsObject(where, options, ['stepHz', 'maxSubsteps', 'integrator', 'xpbdIterations', 'inertia', ...kJumpOptions]);
  const jumps = jumpOptions(where, opts, rigJumps);
  const integrator = opts.integrator === undefined ? 'vrm' : checkOneOf(`${where}: integrator`, opts.integrator, kIntegrators);
  const { maxStepHz, maxSubsteps: maxSubstepsLimit, maxXpbdIterations, integrators } = limits;
  const stepHz = opts.stepHz === undefined ? 0 : checkRange(`${where}: stepHz`, opts.stepHz, 1, maxStepHz);
  const maxSubsteps = opts.maxSubsteps === undefined
    ? 0 : checkInteger(`${where}: maxSubsteps`, opts.maxSubsteps, 1, maxSubstepsLimit);
  let xpbdIterations = integrators.xpbd.xpbdIterations;
  if (opts.xpbdIterations !== undefined) {
    xpbdIterations = checkInteger(`${where}: xpbdIterations`, opts.xpbdIterations, 1, maxXpbdIterations);
    if (integrator !== 'xpbd') throw new RangeError(`${where}: xpbdIterations only applies to integrator 'xpbd'`);
  }
  const inertia = opts.inertia === undefined ? undefined : checkRange(`${where}: inertia`, opts.inertia, 0, 1);
  return { integrator, stepHz, maxSubsteps, xpbdIterations, inertia, jumps };
}

// jumpDistance and jumpAngle of an options object, checked, over `defaults` (a rig's).
function jumpOptions(where, options, defaults) {
  const out = { ...defaults };
  for (const key of kJumpOptions) {
    if (options[key] !== undefined) out[key] = checkNonNegative(`${where}: ${key}`, options[key]);
  }
  return out;
}

// The colliders (a list, or a preset's name), the avatar's bones and hitRadius of loadRig's
// options, checked, as the typed input the bindings read (no bytes for none).
function typedRigOptions(where, options) {
  const { colliders, avatarBones, hitRadius, limits } = options;
  if (colliders === undefined && avatarBones === undefined && hitRadius === undefined && limits === undefined) {
    return new Uint8Array(0);
  }
  const out = {};
  if (avatarBones !== undefined) out.avatarBones = checkedAvatarBones(`${where}: avatarBones`, avatarBones);
  if (limits !== undefined) out.limits = checkedLimits(`${where}: limits`, limits);
  if (hitRadius !== undefined) out.hitRadius = checkNonNegative(`${where}: hitRadius`, hitRadius);
  if (typeof colliders === 'string') {
    if (!kColliderPresets.includes(colliders)) {
      throw new RangeError(`${where}: colliders must be an array or one of ${kColliderPresets.join(', ')}, got '${colliders}'`);
    }
    out.preset = colliders;
  } else if (colliders !== undefined) {
    if (!Array.isArray(colliders)) throw new TypeError(`${where}: colliders must be an array or '${kColliderPresets[0]}'`);
    out.colliders = checkDenseArray(`${where}: colliders`, colliders).map((c, i) => colliderJson(`${where}: colliders[${i}]`, c));
  }
  return encodeTyped(`${where}: options`, out);
}

// The drivers' bound (kMaxDriverEntry, springbones.h): a rest pose beyond it is no pose a driver takes.
const kMaxMatrixEntry = 1e12;

// loadRig's `avatarBones`: bone names to rest world matrices, each 16 finite numbers (an array or a
// typed array, column-major as three.js's Matrix4.elements), within +-1e12.
function checkedAvatarBones(where, bones) {
  if (bones === null || typeof bones !== 'object' || Array.isArray(bones)) {
    throw new TypeError(`${where} must be an object from bone names to rest world matrices`);
  }
  const out = {};
  for (const [name, matrix] of Object.entries(bones)) {
    const at = `${where}.${name}`;
    if (!(Array.isArray(matrix) || ArrayBuffer.isView(matrix)) || matrix.length !== 16) {
      throw new TypeError(`${at} must be 16 numbers (a column-major matrix)`);
    }
    out[name] = Array.from(matrix, (v, i) => {
      checkFinite(`${at}[${i}]`, v);
      if (Math.abs(v) > kMaxMatrixEntry) throw new RangeError(`${at}[${i}] must be within +-1e12, got ${v}`);
      return v;
    });
  }
  return out;
}

const kColliderShapes = ['sphere', 'capsule', 'plane'];

// One collider of loadRig's options, checked: a sphere, a capsule (a tail) or a plane (a normal),
// as `shape` says or, without it, as a tail makes it a capsule. Sphere and capsule take `inside`.
function colliderJson(where, c) {
  if (c === null || typeof c !== 'object' || Array.isArray(c)) throw new TypeError(`${where} must be an object`);
  checkKeys(where, c, ['node', 'shape', 'offset', 'radius', 'tail', 'normal', 'inside']);
  checkNonEmptyString(`${where}.node`, c.node, 'a string (a node name)');
  if (c.shape !== undefined) checkOneOf(`${where}.shape`, c.shape, kColliderShapes);
  const shape = c.shape ?? (c.tail !== undefined ? 'capsule' : 'sphere');
  const only = (key, shapes) => {
    if (c[key] !== undefined && !shapes.includes(shape)) {
      throw new TypeError(`${where}.${key} is not a property of a ${shape} collider`);
    }
  };
  only('tail', ['capsule']);
  only('normal', ['plane']);
  only('radius', ['sphere', 'capsule']);
  only('inside', ['sphere', 'capsule']);
  const collider = { node: c.node, shape, offset: c.offset === undefined ? [0, 0, 0] : checkVec3(`${where}.offset`, c.offset) };
  if (shape === 'plane') {
    const normal = c.normal === undefined ? [0, 0, 1] : checkVec3(`${where}.normal`, c.normal);
    if (normal.every((v) => v === 0)) throw new RangeError(`${where}.normal must not be [0, 0, 0]`);
    collider.normal = scaledDirection(normal);
    return collider;
  }
  collider.radius = checkNonNegative(`${where}.radius`, c.radius);
  if (shape === 'capsule') collider.tail = c.tail === undefined ? [0, 0, 0] : checkVec3(`${where}.tail`, c.tail);
  if (c.inside !== undefined) {
    if (typeof c.inside !== 'boolean') throw new TypeError(`${where}.inside must be a boolean`);
    collider.inside = c.inside;
  }
  return collider;
}

const kColliderPresets = ['dcl-body'];

/**
 * instance.setColliders' arguments, checked, as the typed input the bindings read
 * (readColliderOptions, springbones/boundary.h): `colliders` as loadRig's (an array, or
 * 'dcl-body'), or null for none; `options` {avatarBones?, scale?, omit?}, scale and omit (names
 * from `limits.bodyColliderShapes`) only with 'dcl-body'.
 */
export function colliderChange(where, colliders, options, limits) {
  const opts = optionsObject(where, options, ['avatarBones', 'scale', 'omit']);
  const out = {};
  if (opts.avatarBones !== undefined) out.avatarBones = checkedAvatarBones(`${where}: avatarBones`, opts.avatarBones);
  if (typeof colliders === 'string') {
    if (!kColliderPresets.includes(colliders)) {
      throw new RangeError(`${where}: colliders must be an array, null or one of ${kColliderPresets.join(', ')}, got '${colliders}'`);
    }
    out.preset = colliders;
  } else if (colliders !== null) {
    if (!Array.isArray(colliders)) throw new TypeError(`${where}: colliders must be an array, null or '${kColliderPresets[0]}'`);
    out.colliders = checkDenseArray(`${where}: colliders`, colliders).map((c, i) => colliderJson(`${where}: colliders[${i}]`, c));
  }
  const onlyBody = (key) => {
    if (out.preset === undefined) throw new TypeError(`${where}: ${key} only applies to '${kColliderPresets[0]}'`);
  };
  if (opts.scale !== undefined) {
    onlyBody('scale');
    out.scale = checkNonNegative(`${where}: scale`, opts.scale);
  }
  if (opts.omit !== undefined) {
    onlyBody('omit');
    if (!Array.isArray(opts.omit)) throw new TypeError(`${where}: omit must be an array of shape names`);
    out.omit = checkDenseArray(`${where}: omit`, opts.omit).map((name, i) => checkOneOf(`${where}: omit[${i}]`, name, limits.bodyColliderShapes));
  }
  return encodeTyped(`${where}: colliders`, out);
}

// loadRig's `limits`: joint names to one limit each, as VRMC_springBone_limit spells it. Types and
// shapes are checked here; the core clamps angles out of the draft's ranges with a warning.
function checkedLimits(where, limits) {
  if (limits === null || typeof limits !== 'object' || Array.isArray(limits)) {
    throw new TypeError(`${where} must be an object of joint names`);
  }
  const out = Object.create(null);  // a joint may be called __proto__
  for (const [name, limit] of Object.entries(limits)) {
    const at = `${where}[${JSON.stringify(name)}]`;
    if (limit === null || typeof limit !== 'object' || Array.isArray(limit)) {
      throw new TypeError(`${at} must be an object`);
    }
    const kinds = Object.keys(limit);
    if (kinds.length !== 1 || !['cone', 'hinge', 'spherical'].includes(kinds[0])) {
      throw new TypeError(`${at} must have exactly one of cone, hinge, spherical`);
    }
    const kind = kinds[0];
    const shape = limit[kind];
    if (shape === null || typeof shape !== 'object' || Array.isArray(shape)) {
      throw new TypeError(`${at}.${kind} must be an object`);
    }
    const angles = kind === 'spherical' ? ['pitch', 'yaw'] : ['angle'];
    checkKeys(`${at}.${kind}`, shape, [...angles, 'rotation']);
    const checked = {};
    for (const key of angles) checked[key] = checkFinite(`${at}.${kind}.${key}`, shape[key]);
    if (shape.rotation !== undefined) {
      const r = shape.rotation;
      if (!(Array.isArray(r) || ArrayBuffer.isView(r)) || r.length !== 4) {
        throw new TypeError(`${at}.${kind}.rotation must be 4 numbers (x, y, z, w)`);
      }
      checked.rotation = Array.from(r, (v, i) => checkFinite(`${at}.${kind}.rotation[${i}]`, v));
      if (checked.rotation.every((v) => v === 0)) {
        throw new RangeError(`${at}.${kind}.rotation must not be [0, 0, 0, 0]`);
      }
    }
    out[name] = { [kind]: checked };
  }
  return out;
}
