// springBones (loadRig's argument) and which of its models entries applies: the options
// contentHash, entity and bodyShape (docs/semantics.md, "Which models entry"). The creator tools
// choose the entry with the same function (resolveHash), so that both modules agree.

import { checkNonEmptyString, checkWellFormed } from './arguments.js';
import { SpringBonesError, call, takeError, withCause } from './errors.js';
import { checkStringBound, encodeTyped } from './typed_value.js';
import { withBytes } from './wasm_memory.js';

/** The options that say which models entry applies (loadRig, detectSpringBones). */
export const kHashOptions = ['contentHash', 'entity', 'bodyShape'];

// Which models key applies (docs/semantics.md, "Which models entry"): the caller's hash, then the entity's; '' lets
// the core hash the GLB itself.
export function resolveHash(m, where, options) {
  const { contentHash, entity, bodyShape } = options;
  if (contentHash !== undefined) checkStringBound(`${where}: contentHash`, checkNonEmptyString(`${where}: contentHash`, contentHash));
  if (entity !== undefined || bodyShape !== undefined) {
    if (entity === undefined) throw new TypeError(`${where}: bodyShape needs an entity`);
    if (typeof bodyShape !== 'string') {
      throw new TypeError(`${where}: with an entity, bodyShape must be a string (a body shape URN)`);
    }
    checkStringBound(`${where}: bodyShape`, checkNonEmptyString(`${where}: bodyShape`, bodyShape));
  }
  const typedEntity = entity === undefined ? undefined : encodeTyped(`${where}: entity`, parsedArgument(
    `${where}: entity`, entity, 'entity-bad-json', 'an object or JSON text'));
  if (contentHash !== undefined) return contentHash;
  if (typedEntity === undefined) return '';
  const hash = call(() => withBytes(m, typedEntity, (ptr, size) => m.mainFileHashFor(ptr, size, bodyShape)));
  if (hash === '') throw takeError(m);
  return hash;
}

// data.springBones as typed input: an object, JSON text (at most maxMetadataBytes), or
// null/undefined for none.
export function typedMetadata(springBones, limits) {
  const what = 'loadRig: springBones';
  if (springBones === null || springBones === undefined) return encodeTyped(what, null);
  if (typeof springBones === 'string' && springBones.length > limits.maxMetadataBytes / 3 &&
      new TextEncoder().encode(springBones).length > limits.maxMetadataBytes) {
    throw new SpringBonesError('limit-exceeded',
      `springBones JSON is more than the limit of ${limits.maxMetadataBytes} bytes`);
  }
  return encodeTyped(what, parsedArgument(what, springBones, 'metadata-bad-json',
                                          'an object, JSON text, null or undefined'));
}

// An object argument, or JSON text parsed here (a SpringBonesError with `badJsonCode` when it does
// not parse).
function parsedArgument(what, value, badJsonCode, described) {
  if (typeof value === 'string') {
    checkWellFormed(what, value);
    try {
      return JSON.parse(value);
    } catch (cause) {
      throw withCause(new SpringBonesError(badJsonCode, `${what} JSON does not parse: ${cause.message}`), cause);
    }
  }
  if (value === null || typeof value !== 'object') throw new TypeError(`${what} must be ${described}`);
  return value;
}
