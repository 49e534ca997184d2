// Generates tests/fixtures/validation_cases.json: springBones inputs judged by the real
// SpringBonesData.validate of @dcl/schemas (Ajv 8, allErrors), so the C++ validator
// (src/creator_tools/validation.cpp) can be checked against it case by case (tests/native/validation_test.cpp).
//
//   node scripts/generate/make_validation_cases.mjs        (needs `npm install` first)
//
// Each case: { name, input, valid, errors, content, representations, catalystErrors, contents,
//              itemCatalystErrors }
//   valid, errors    SpringBonesData.validate(input) and its errors as `instancePath message`.
//   content, representations
//                    an entity around the input (entity.content and metadata.data.representations):
//                    some models keys are the mainFile hash of a representation, some are not.
//   catalystErrors   what the catalyst's spring-bone rule (newest core-libs wording) answers for
//                    that entity: the schema errors as it words them, else the key and bone-name
//                    errors. The schema part comes from @dcl/schemas itself; the cross-checks are
//                    restated below in a few lines of JavaScript (the catalyst's library is not on
//                    npm), so toLowerCase, Set and key order are JavaScript's own.
//   contents, itemCatalystErrors
//                    the same wearable as a Builder item { contents: {file: hash}, data:
//                    { representations, springBones } }, and the catalyst's answer for it once
//                    deployed (as the entity whose content lists those contents).
//
// JSON has no NaN or Infinity. Such numbers are validated as real numbers here and written to the
// file as the object {"$nonFinite": "NaN" | "Infinity" | "-Infinity"}; the C++ test turns that
// object back into the double before validating. No generated input uses the key "$nonFinite".
//
// Objects are built with their keys in UTF-8 byte order. JavaScript enumerates array-index keys
// ("0", "17") first and the rest in insertion order, which the C++ validator reproduces from
// nlohmann::json's sorted keys, so the error lists can be compared in order, not only as sets.
// Everything is drawn from a seeded PRNG: the output is the same on every run.

import { mkdirSync, writeFileSync } from 'node:fs'
import { dirname, join } from 'node:path'
import { fileURLToPath } from 'node:url'
import { SpringBonesData } from '@dcl/schemas'
import { seededRandom } from '../lib/fixtures/random.mjs'

const kSeed = 0x5eed5b0e
const kOutput = join(dirname(fileURLToPath(import.meta.url)), '..', '..', 'tests', 'fixtures', 'validation_cases.json')

const random = seededRandom(kSeed)
const randInt = (lo, hi) => lo + Math.floor(random() * (hi - lo + 1))
const pick = (list) => list[Math.floor(random() * list.length)]
const chance = (p) => random() < p

// ---------------------------------------------------------------------------------------------
// Building blocks

const kBase32 = 'abcdefghijklmnopqrstuvwxyz234567'
function fakeCid() {
  let s = 'bafkrei'
  for (let i = 0; i < 52; ++i) s += kBase32[randInt(0, 31)]
  return s
}
const H = 'bafkreialsvt77jvpy673cnugp5ggnxfaalfncufweayuk3jbxskh3pelkm'
const H2 = 'bafkreigreflbn4w3a36rgg2ywlhf2asebqlsd4skg5q5djpklcdcjkbjvi'
const B = 'Hair_springBone_L'

const kBoneStems = ['Hair', 'Earring', 'Tail', 'Cape', 'Skirt', 'Ribbon', 'Ear', 'Chain', 'Tassel']
function boneName() {
  const stem = pick(kBoneStems)
  const token = pick(['springbone', 'SpringBone', 'SPRINGBONE', 'springBone', 'Springbone', 'sPrInGbOnE'])
  const side = pick(['', '_L', '_R', '_01', '.001', '_tip'])
  if (chance(0.12)) return `${stem}${side || '_001'}` // schema accepts it; the catalyst does not
  return pick([`${token}_${stem}${side}`, `${stem}_${token}${side}`, `${stem}${token}${side}`])
}

// Numbers in a range, drawn in the shapes metadata really has: integers, short decimals,
// full-precision doubles and the bounds themselves.
function numberIn(min, max) {
  switch (randInt(0, 5)) {
    case 0: return min
    case 1: return max
    case 2: return randInt(Math.ceil(min), Math.floor(max))
    case 3: return Math.round((min + random() * (max - min)) * 100) / 100
    default: return min + random() * (max - min)
  }
}

function validParams() {
  const p = {
    stiffness: numberIn(0, 4),
    gravityPower: numberIn(0, 2),
    gravityDir: chance(0.5) ? [0, -1, 0] : [numberIn(-10, 10), numberIn(-10, 10), numberIn(-10, 10)],
    drag: numberIn(0, 1)
  }
  if (chance(0.3)) p.center = chance(0.8) ? pick(['Avatar_Hips', 'Avatar_Head', 'Avatar_Spine2', '']) : null
  if (chance(0.7)) p.isRoot = chance(0.85) ? chance(0.8) : null
  if (chance(0.1)) p.hitRadius = numberIn(0, 1) // Unity's DTO field: unknown keys are allowed in a bone
  return p
}

function validDoc(hashes = randInt(1, 3), bones = randInt(1, 4)) {
  const models = {}
  for (let h = 0; h < hashes; ++h) {
    const entry = {}
    for (let b = 0; b < bones; ++b) entry[boneName()] = validParams()
    models[fakeCid()] = entry
  }
  return { version: 1, models }
}

const P = () => ({ stiffness: 2, gravityPower: 0, gravityDir: [0, -1, 0], drag: 0.5 })
const M = (bone) => ({ version: 1, models: { [H]: { [B]: bone } } })
const withParam = (key, value) => M({ ...P(), [key]: value })
const withoutParam = (...keys) => {
  const p = P()
  for (const k of keys) delete p[k]
  return M(p)
}

// The next double up or down from x.
function nextAfter(x, direction) {
  if (x === 0) return direction > 0 ? Number.MIN_VALUE : -Number.MIN_VALUE
  const f = new Float64Array([x])
  const bits = new BigInt64Array(f.buffer)
  bits[0] += (x > 0) === (direction > 0) ? 1n : -1n // away from zero grows the magnitude bits
  return f[0]
}

// ---------------------------------------------------------------------------------------------
// The cases

const cases = []
const add = (name, input) => cases.push({ name, input })

// The named vectors: the schema's bounds, types and shapes one at a time (V* valid, I* invalid).
add('V1 base params', M(P()))
add('V2 center and isRoot', M({ ...P(), center: 'Avatar_Hips', isRoot: true }))
add('V3 empty models', { version: 1, models: {} })
add('V4 hash with no bones', { version: 1, models: { [H]: {} } })
add('V5 inclusive maxima', M({ stiffness: 4, gravityPower: 2, gravityDir: [10, -10, 0], drag: 1 }))
add('V6 zeros and zero gravityDir', M({ stiffness: 0, gravityPower: 0, gravityDir: [0, 0, 0], drag: 0 }))
add('V7 version 1.0', { version: 1.0, models: {} })
add('V8 center null', withParam('center', null))
add('V8 isRoot null', withParam('isRoot', null))
add('V9 unknown key in bone', withParam('foo', 1))
add('V10 non-cid key and non-spring bone name', { version: 1, models: { 'not-a-cid': { Avatar_Head: P() } } })
add('I1 stiffness 4.01', withParam('stiffness', 4.01))
add('I2 stiffness -1', withParam('stiffness', -1))
add('I3 gravityPower 2.5', withParam('gravityPower', 2.5))
add('I4 drag 1.5', withParam('drag', 1.5))
add('I5 missing version', { models: {} })
add('I6 version 2', { version: 2, models: {} })
add('I7 version string', { version: '1', models: {} })
add('I8 missing models', { version: 1 })
add('I9 gravityDir two items', withParam('gravityDir', [0, -1]))
add('I10 gravityDir four items', withParam('gravityDir', [0, -1, 0, 0]))
add('I11 gravityDir component -11', withParam('gravityDir', [0, -11, 0]))
add('I12 gravityDir string component', withParam('gravityDir', [0, 'down', 0]))
add('I13 extra top-level key', { version: 1, models: {}, extra: true })
add('I14 stiffness NaN', withParam('stiffness', NaN))
add('I15 stiffness Infinity', withParam('stiffness', Infinity))
add('I16 gravityDir NaN component', withParam('gravityDir', [0, NaN, 0]))
add('I17 stiffness string', withParam('stiffness', '2'))
add('I18 drag missing', withoutParam('drag'))
add('I19 center number', withParam('center', 5))
add('I20 isRoot string', withParam('isRoot', 'yes'))
add('I21 bone null', { version: 1, models: { [H]: { b: null } } })
add('I22 model array', { version: 1, models: { [H]: [] } })
add('I23 null', null)

// Every numeric field at, inside and just outside each inclusive bound.
const kRanges = [
  ['stiffness', 0, 4],
  ['gravityPower', 0, 2],
  ['drag', 0, 1]
]
function boundaryValues(min, max) {
  return [
    ['min', min], ['max', max], ['mid', (min + max) / 2],
    ['min-next-down', nextAfter(min, -1)], ['max-next-up', nextAfter(max, 1)],
    ['min-next-up', nextAfter(min, 1)], ['max-next-down', nextAfter(max, -1)],
    ['min-1e-9', min - 1e-9], ['max+1e-9', max + 1e-9],
    ['min-0.01', min - 0.01], ['max+0.01', max + 0.01],
    ['min-1', min - 1], ['max+1', max + 1],
    ['max*10', max * 10], ['-max', -max],
    ['1e308', 1e308], ['-1e308', -1e308], ['MAX_VALUE', Number.MAX_VALUE], ['-MAX_VALUE', -Number.MAX_VALUE],
    ['MIN_VALUE', Number.MIN_VALUE], ['-MIN_VALUE', -Number.MIN_VALUE], ['-0', -0],
    ['2^53+2', 2 ** 53 + 2], ['-(2^53+2)', -(2 ** 53 + 2)], ['1e21', 1e21]
  ]
}
for (const [key, min, max] of kRanges) {
  for (const [label, value] of boundaryValues(min, max)) add(`${key} ${label}`, withParam(key, value))
}
for (let axis = 0; axis < 3; ++axis) {
  for (const [label, value] of boundaryValues(-10, 10)) {
    const dir = [0, -1, 0]
    dir[axis] = value
    add(`gravityDir[${axis}] ${label}`, withParam('gravityDir', dir))
  }
}

// Values of the wrong type, for every field and every gravityDir slot.
const kWrongTypes = [
  ['string number', '1'], ['empty string', ''], ['word', 'abc'], ['null', null], ['true', true], ['false', false],
  ['empty array', []], ['array of one', [1]], ['array of three', [0, -1, 0]], ['empty object', {}],
  ['object', { value: 1 }], ['NaN', NaN], ['Infinity', Infinity], ['-Infinity', -Infinity]
]
for (const key of ['stiffness', 'gravityPower', 'drag', 'gravityDir']) {
  for (const [label, value] of kWrongTypes) add(`${key} ${label}`, withParam(key, value))
}
for (let axis = 0; axis < 3; ++axis) {
  for (const [label, value] of kWrongTypes) {
    const dir = [0, -1, 0]
    dir[axis] = value
    add(`gravityDir[${axis}] ${label}`, withParam('gravityDir', dir))
  }
}
const kCenterValues = [
  ['name', 'Avatar_Hips'], ['empty', ''], ['null', null], ['number', 5], ['zero', 0], ['true', true],
  ['false', false], ['array', ['Avatar_Hips']], ['object', { name: 'Avatar_Hips' }], ['NaN', NaN]
]
for (const [label, value] of kCenterValues) add(`center ${label}`, withParam('center', value))
const kIsRootValues = [
  ['true', true], ['false', false], ['null', null], ['one', 1], ['zero', 0], ['string true', 'true'],
  ['empty string', ''], ['array', [true]], ['object', {}], ['Infinity', Infinity]
]
for (const [label, value] of kIsRootValues) add(`isRoot ${label}`, withParam('isRoot', value))

// Missing required fields: each one, each pair, all of them, and optional ones left out.
const kRequired = ['stiffness', 'gravityPower', 'gravityDir', 'drag']
for (const key of kRequired) add(`missing ${key}`, withoutParam(key))
for (let i = 0; i < 4; ++i) {
  for (let j = i + 1; j < 4; ++j) add(`missing ${kRequired[i]} and ${kRequired[j]}`, withoutParam(kRequired[i], kRequired[j]))
}
add('missing all params', M({}))
add('only optional params', M({ center: 'Avatar_Hips', isRoot: true }))
add('missing params but wrong types elsewhere', M({ stiffness: 'x', center: 3 }))
add('missing version and models', {})
add('missing version, models null', { models: null })
add('missing models, version 2', { version: 2 })

// Extra keys: forbidden at the top level, allowed inside a bone entry.
add('extra key null', { version: 1, models: {}, extra: null })
add('two extra keys', { version: 1, models: {}, a: 1, b: 2 })
add('three extra keys and missing models', { version: 1, x: 1, y: {}, z: [] })
add('extra key named like a param', { version: 1, models: {}, stiffness: 2 })
add('extra key __proto__', Object.defineProperty({ version: 1, models: {} }, '__proto__', { value: {}, enumerable: true, writable: true, configurable: true }))
add('extra key constructor', { version: 1, models: {}, constructor: 1 })
add('extra key empty string', { version: 1, models: {}, '': 0 })
add('extra key and invalid version', { version: 3, models: {}, extra: true })
add('Version capitalised', { Version: 1, models: {} })
for (const [label, value] of [['hitRadius', 0.02], ['null', null], ['object', { a: [1, 2] }], ['array', []], ['string', 'x'], ['nested nulls', { a: null, b: [null] }]]) {
  add(`bone extra key ${label}`, withParam(label === 'hitRadius' ? 'hitRadius' : `extra_${label.replace(' ', '_')}`, value))
}
add('bone many extra keys', M({ ...P(), colliders: [], hitRadius: 0.1, name: 'x', version: 2, models: null }))
add('bone extra key __proto__', M(Object.defineProperty(P(), '__proto__', { value: null, enumerable: true, writable: true, configurable: true })))

// version.
const kVersions = [
  ['0', 0], ['2', 2], ['1.0', 1.0], ['string 1', '1'], ['1.5', 1.5], ['null', null], ['-1', -1], ['true', true],
  ['false', false], ['empty array', []], ['[1]', [1]], ['object', { v: 1 }], ['NaN', NaN], ['Infinity', Infinity],
  ['-Infinity', -Infinity], ['1e300', 1e300], ['1+epsilon', 1 + Number.EPSILON], ['0.9999999999999999', 0.9999999999999999],
  ['-0', -0], ['empty string', ''], ['string 1.0', '1.0'], ['2^53', 2 ** 53], ['MIN_VALUE', Number.MIN_VALUE]
]
for (const [label, value] of kVersions) add(`version ${label}`, { version: value, models: {} })
add('version 2 with invalid bone', { version: 2, models: { [H]: { [B]: { ...P(), drag: 2 } } } })

// gravityDir lengths 0..5, in and out of range, and nested non-numbers.
for (let n = 0; n <= 5; ++n) {
  add(`gravityDir length ${n}`, withParam('gravityDir', Array.from({ length: n }, (_, i) => i - 1)))
  add(`gravityDir length ${n} out of range`, withParam('gravityDir', Array.from({ length: n }, (_, i) => (i % 2 ? -20 : 20))))
  add(`gravityDir length ${n} of nulls`, withParam('gravityDir', Array.from({ length: n }, () => null)))
  add(`gravityDir length ${n} of strings`, withParam('gravityDir', Array.from({ length: n }, (_, i) => String(i))))
}
add('gravityDir nested arrays', withParam('gravityDir', [[0], [-1], [0]]))
add('gravityDir objects', withParam('gravityDir', [{}, { y: -1 }, {}]))
add('gravityDir booleans', withParam('gravityDir', [false, true, false]))
add('gravityDir mixed bad', withParam('gravityDir', [NaN, 'x', 11, null, 0]))
add('gravityDir fourth item not a number', withParam('gravityDir', [0, -1, 0, 'extra']))
add('gravityDir fifth item out of range', withParam('gravityDir', [0, -1, 0, 0, 99]))
add('gravityDir string', withParam('gravityDir', '0,-1,0'))
add('gravityDir object with indices', withParam('gravityDir', { 0: 0, 1: -1, 2: 0 }))
add('gravityDir number', withParam('gravityDir', -1))

// The shape of models and of the document.
for (const [label, value] of [['null', null], ['array', []], ['array of object', [{}]], ['string', 'x'], ['number', 1], ['true', true], ['false', false]]) {
  add(`models ${label}`, { version: 1, models: value })
  add(`model entry ${label}`, { version: 1, models: { [H]: value } })
  add(`bone entry ${label}`, { version: 1, models: { [H]: { [B]: value } } })
  add(`document ${label}`, value)
}
add('document empty string', '')
add('document zero', 0)
add('document array of valid doc', [{ version: 1, models: {} }])
add('nested nulls everywhere', { version: null, models: { [H]: { [B]: { stiffness: null, gravityPower: null, gravityDir: [null, null, null], drag: null, center: null, isRoot: null } } } })
add('nested nulls with a null model', { version: 1, models: { [H]: null, [H2]: { [B]: null } } })
add('mixed good and bad models', { version: 1, models: { [H]: { [B]: P() }, [H2]: [], x: { y: 'z' } } })

// Keys that need escaping or sort unusually: JSON pointer '/' and '~', array-index keys that
// JavaScript enumerates first, non-ASCII, control characters, quotes, very long keys.
const kOddKeys = [
  'male/AnimeLong.glb', 'a~b', '~1', '/', '~', '0', '1', '9', '10', '007', '4294967294', '4294967295', '-1', '1.5',
  '', ' ', 'Ünïcødé', '髪_springbone', '😀springbone', 'quote"key', 'back\\slash', 'tab\tkey', 'nl\nkey', 'ctl\u0001\u001fkey',
  'del\u007fkey', 'line\u2028sep', 'constructor', '__proto__', 'toString', 'hasOwnProperty',
  'x'.repeat(99), 'y'.repeat(100), 'z'.repeat(101), 'springbone'.repeat(30), '😀'.repeat(60), 'é'.repeat(120),
  '"'.repeat(60), 'SPR\u0130NGBONE', 'ſpringbone', 'springbone\u0000nul'
]
const defineKey = (object, key, value) =>
  Object.defineProperty(object, key, { value, enumerable: true, writable: true, configurable: true })
for (const key of kOddKeys) {
  const label = [...JSON.stringify(key)].slice(0, 24).join('') // whole code points: no lone surrogates
  add(`odd hash key ${label} valid`, { version: 1, models: defineKey({}, key, { [B]: P() }) })
  add(`odd hash key ${label} invalid bone`, { version: 1, models: defineKey({}, key, { [B]: { ...P(), stiffness: 9 } }) })
  add(`odd bone key ${label} valid`, { version: 1, models: { [H]: defineKey({}, key, P()) } })
  add(`odd bone key ${label} missing drag`, { version: 1, models: { [H]: defineKey({}, key, { ...P(), drag: undefined }) } })
}
{
  // Several array-index and ordinary keys together: the error order shows the key order.
  const models = {}
  for (const key of ['b', '10', 'a', '2', '0', 'Z', '007']) models[key] = { [`${key}_springbone`]: { ...P(), drag: 7 } }
  add('index keys enumerate first', { version: 1, models })
  const bones = {}
  for (const key of ['tail', '3', '21', 'Hair', '100', '4294967295']) bones[key] = { stiffness: -1 }
  add('index bone keys enumerate first', { version: 1, models: { [H]: bones } })
}

// Many hashes and bones, valid and with a few errors scattered through them.
for (const [hashes, bones] of [[20, 5], [5, 30], [16, 10], [48, 2], [2, 64]]) {
  const doc = validDoc(hashes, bones)
  add(`many ${hashes}x${bones} valid`, doc)
  const broken = structuredClone(doc)
  const keys = Object.keys(broken.models)
  for (let k = 0; k < 6; ++k) {
    const model = broken.models[pick(keys)]
    const bone = model[pick(Object.keys(model))]
    const field = pick(['stiffness', 'gravityPower', 'drag', 'gravityDir', 'isRoot'])
    bone[field] = pick([-1, 99, 'x', null, [1], NaN])
  }
  add(`many ${hashes}x${bones} with errors`, broken)
}
{
  const models = {}
  for (let h = 0; h < 12; ++h) models[fakeCid()] = {}
  add('many empty models', { version: 1, models })
}
add('13 bones under one hash', { version: 1, models: { [H]: Object.fromEntries(Array.from({ length: 13 }, (_, i) => [`SpringBone_${i}`, P()])) } })

// Random valid documents.
for (let i = 0; i < 80; ++i) add(`random valid ${i}`, validDoc(randInt(0, 4), randInt(0, 6)))

// Random documents with one to four random faults.
const kBadValues = [
  -1, -0.5, -1e-9, 4.5, 11, -11, 1e9, '1', '', 'x', null, true, false, [], [0, -1, 0], {}, { a: 1 }, NaN, Infinity, -Infinity
]
const kMutations = [
  (d) => { d.version = pick([0, 2, '1', 1.5, null, true, NaN, 1.0, 1]) },
  (d) => { delete d.version },
  (d) => { delete d.models },
  (d) => { d[pick(['extra', 'Models', 'springBones', 'colliders'])] = pick(kBadValues) },
  (d) => { d.models = pick([null, [], 'x', 3, true]) },
  (d, h) => { d.models[h] = pick([null, [], 'x', 3, true]) },
  (d, h, b) => { d.models[h][b] = pick([null, [], 'x', 3, true, {}]) },
  (d, h, b) => { d.models[h][b][pick(['stiffness', 'gravityPower', 'drag', 'center', 'isRoot', 'gravityDir'])] = pick(kBadValues) },
  (d, h, b) => { delete d.models[h][b][pick(kRequired)] },
  (d, h, b) => { d.models[h][b].gravityDir = Array.from({ length: randInt(0, 5) }, () => (chance(0.7) ? numberIn(-12, 12) : pick(kBadValues))) },
  (d, h, b) => { d.models[h][b][pick(['stiffness', 'gravityPower', 'drag'])] = numberIn(-1, 5) },
  (d, h, b) => { d.models[h][b][pick(['hitRadius', 'foo', 'center'])] = pick(['Avatar_Hips', null, 0.2, {}]) },
  (d, h) => { d.models[h][pick(['Avatar_Head', 'bone.001', 'x/y', '5'])] = validParams() },
  (d) => { d.models[pick([H, H2, 'male/AnimeLong.glb', fakeCid()])] = { [boneName()]: validParams() } }
]
for (let i = 0; i < 260; ++i) {
  const doc = validDoc(randInt(1, 3), randInt(1, 3))
  const faults = randInt(1, 4)
  for (let f = 0; f < faults; ++f) {
    // A fault that needs a model or bone is skipped once earlier faults have removed them.
    const models = doc.models
    const hashes = models && typeof models === 'object' && !Array.isArray(models) ? Object.keys(models) : []
    const hash = hashes.length ? pick(hashes) : undefined
    const model = hash !== undefined ? models[hash] : undefined
    const bones = model && typeof model === 'object' && !Array.isArray(model) ? Object.keys(model) : []
    const bone = bones.length ? pick(bones) : undefined
    const boneValue = bone !== undefined ? model[bone] : undefined
    const isObject = (v) => v !== null && typeof v === 'object' && !Array.isArray(v)
    const mutation = randInt(0, kMutations.length - 1)
    const needs = mutation === 13 ? 'models' : mutation === 5 ? 'hash' : mutation === 12 ? 'model'
      : mutation === 6 ? 'bone' : mutation >= 7 ? 'boneObject' : 'nothing'
    if (needs === 'models' && !isObject(models)) continue
    if (needs === 'hash' && hash === undefined) continue
    if (needs === 'model' && !isObject(model)) continue
    if (needs === 'bone' && bone === undefined) continue
    if (needs === 'boneObject' && !isObject(boneValue)) continue
    kMutations[mutation](doc, hash, bone)
  }
  add(`random faults ${i}`, doc)
}

// ---------------------------------------------------------------------------------------------
// Judging and writing

function utf8Compare(a, b) {
  return Buffer.compare(Buffer.from(a, 'utf8'), Buffer.from(b, 'utf8'))
}

// Rebuilds objects with keys in UTF-8 byte order (see the header); drops undefined members as
// JSON would.
function sortKeys(value) {
  if (Array.isArray(value)) return value.map(sortKeys)
  if (value === null || typeof value !== 'object') return value
  const out = {}
  for (const key of Object.keys(value).sort(utf8Compare)) {
    if (value[key] !== undefined) defineKey(out, key, sortKeys(value[key]))
  }
  return out
}

// The catalyst quotes a field as JSON.stringify(field) minus its opening quote, cut to the
// field's length, or to 99 units plus '...' when the field is longer than 100.
// A cut can leave half of a surrogate pair, which neither UTF-8 nor this file (nlohmann::json
// rejects "\ud83d" alone) can carry: it becomes U+FFFD, as in the C++ validator.
function catalystField(field) {
  const quoted = JSON.stringify(field)
  const cut = field.length > 100 ? `${quoted.slice(1, 100)}...` : quoted.slice(1, field.length + 1)
  return cut.toWellFormed()
}

// The catalyst's spring-bone rule, restated: falsy springBones pass; schema errors alone if any;
// else a key that no representation's mainFile hashes to, and a bone name without 'springbone'.
function catalystErrors(entity) {
  const springBones = entity.metadata.data.springBones
  if (!springBones) return []
  if (!SpringBonesData.validate(springBones)) {
    return SpringBonesData.validate.errors.map((e) => `springBones${catalystField(e.instancePath)} ${e.message}`)
  }
  const current = new Set()
  for (const representation of entity.metadata.data.representations) {
    const entry = entity.content.find((c) => c.file === representation.mainFile)
    if (entry) current.add(entry.hash)
  }
  const errors = []
  for (const [hash, bones] of Object.entries(springBones.models)) {
    if (!current.has(hash)) {
      errors.push(`springBones.models key ${catalystField(hash)} does not match any current representation hash`)
    }
    for (const bone of Object.keys(bones)) {
      if (!bone.toLowerCase().includes('springbone')) {
        errors.push(`Bone name ${catalystField(bone)} in model ${catalystField(hash)} does not follow the spring bone naming convention`)
      }
    }
  }
  return errors
}

// An entity around the input: most models keys become a representation's mainFile hash, the
// rest are stale; a texture sometimes carries a stale key's hash (non-main files do not count);
// sometimes both body shapes share one GLB.
function entityFor(input) {
  const content = [{ file: 'thumbnail.png', hash: fakeCid() }]
  const representations = []
  const models = input && typeof input === 'object' && !Array.isArray(input) ? input.models : undefined
  const keys = models && typeof models === 'object' && !Array.isArray(models) ? Object.keys(models) : []
  const stale = []
  keys.forEach((key, i) => {
    if (chance(0.8)) {
      const file = `model_${i}.glb`
      content.push({ file, hash: key })
      const shapes = chance(0.3) ? ['urn:decentraland:off-chain:base-avatars:BaseMale', 'urn:decentraland:off-chain:base-avatars:BaseFemale'] : [pick(['urn:decentraland:off-chain:base-avatars:BaseMale', 'urn:decentraland:off-chain:base-avatars:BaseFemale'])]
      for (const shape of shapes) representations.push({ bodyShapes: [shape], mainFile: file, contents: [file, 'thumbnail.png'] })
    } else {
      stale.push(key)
    }
  })
  if (stale.length && chance(0.5)) content.push({ file: 'texture.png', hash: pick(stale) })
  if (representations.length === 0) {
    content.push({ file: 'other.glb', hash: fakeCid() })
    representations.push({ bodyShapes: ['urn:decentraland:off-chain:base-avatars:BaseMale'], mainFile: 'other.glb', contents: ['other.glb'] })
  }
  return { content, representations }
}

// The Builder item form of the same wearable: contents is an object {file: hash}, the first entry
// of a file winning as the entity's content list does. Draws nothing from the PRNG, so the other
// fields of every case are what they were before items were added.
function itemContents(content) {
  const contents = {}
  for (const { file, hash } of content) if (!Object.hasOwn(contents, file)) contents[file] = hash
  return contents
}

// A Builder deploys an item as an entity whose content lists its contents: the catalyst's answer
// for the item is its answer for that entity.
function itemCatalystErrors(item) {
  const content = Object.entries(item.contents).map(([file, hash]) => ({ file, hash }))
  return catalystErrors({ content, metadata: { data: item.data } })
}

const out = []
for (const { name, input } of cases) {
  const sorted = sortKeys(input)
  const valid = SpringBonesData.validate(sorted)
  const errors = (SpringBonesData.validate.errors ?? []).map((e) => `${e.instancePath} ${e.message}`)
  const { content, representations } = entityFor(sorted)
  const entity = { content, metadata: { data: { representations, springBones: sorted } } }
  const contents = itemContents(content)
  const item = { contents, data: { representations, springBones: sorted } }
  out.push({
    name, input: sorted, valid, errors, content, representations, catalystErrors: catalystErrors(entity),
    contents, itemCatalystErrors: itemCatalystErrors(item),
  })
}

const names = new Set()
for (const c of out) {
  if (names.has(c.name)) throw new Error(`duplicate case name ${c.name}`)
  names.add(c.name)
}

const nonFinite = (_key, value) =>
  typeof value === 'number' && !Number.isFinite(value) ? { $nonFinite: String(value) } : value
mkdirSync(dirname(kOutput), { recursive: true })
writeFileSync(kOutput, `[\n${out.map((c) => JSON.stringify(c, nonFinite)).join(',\n')}\n]\n`)

const validCount = out.filter((c) => c.valid).length
const acceptedCount = out.filter((c) => c.catalystErrors.length === 0).length
console.log(`${out.length} cases (${validCount} valid, ${out.length - validCount} invalid; ` +
  `${acceptedCount} accepted by the catalyst rule in their entity) -> ${kOutput}`)
