// Prints the reference content hashes that tests/native/content_hash_test.cpp checks, computed by
// Decentraland's own code: `hashV1` of npm @dcl/hashing (a devDependency; run `npm install` first).
//
//   node scripts/reference/content_hash_reference.mjs
//
// Section 1 uses hashV1 exactly as the Builder and the catalyst do. Section 2 runs the same bundled
// ipfs-unixfs-importer with a smaller chunk size and fan-out, so trees three and more levels deep
// can be checked without a 7.9 GB input; @dcl/hashing does not export the importer, so this part
// evaluates the package's own bundle and picks the functions out of it (same code, same version).
import { createRequire } from 'node:module'
import { readFileSync } from 'node:fs'
import { dirname } from 'node:path'
import hashing from '@dcl/hashing' // a CommonJS bundle: Node sees only its default export

const { hashV1 } = hashing
const require = createRequire(import.meta.url)

// The deterministic byte patterns the C++ tests generate.
const filled = (size, value) => new Uint8Array(size).fill(value)
const mod251 = (size) => {
  const bytes = new Uint8Array(size)
  for (let i = 0; i < size; i++) bytes[i] = i % 251
  return bytes
}

const cases = [
  ['"helloworld"', () => new TextEncoder().encode('helloworld')],
  ['empty', () => new Uint8Array(0)],
  ['mod251(1)', () => mod251(1)],
  ['fill07(262144)   one chunk', () => filled(262144, 7)],
  ['fill07(262145)   two chunks', () => filled(262145, 7)],
  ['fill07(300000)', () => filled(300000, 7)],
  ['mod251(1000000)', () => mod251(1000000)],
  ['mod251(45613056) 174 chunks, one node', () => mod251(174 * 262144)],
  ['mod251(45613057) 175 chunks, two levels', () => mod251(174 * 262144 + 1)],
  ['mod251(46000000)', () => mod251(46000000)]
]

console.log('# 1. hashV1 (chunk 262144, fan-out 174)')
for (const [name, make] of cases) {
  const bytes = make()
  console.log(`${name.padEnd(42)} ${String(bytes.length).padStart(9)}  ${await hashV1(bytes)}`)
}

// --- 2. the same importer with another layout -------------------------------------------------
const bundlePath = require.resolve('@dcl/hashing')
const bundleSource = readFileSync(bundlePath, 'utf8')
// The bundle is CommonJS with top-level declarations; appending a return inside a function
// wrapper exposes the internal names without changing any of its code.
const internals = new Function('module', 'exports', 'require', '__filename', '__dirname',
  `${bundleSource}\n;return { importer, fixedSize, balanced, MemoryBlockstore }`)(
  { exports: {} }, {}, require, bundlePath, dirname(bundlePath))

async function hashWithLayout (bytes, chunkSize, maxChildrenPerNode) {
  const { importer, fixedSize, balanced, MemoryBlockstore } = internals
  async function * once () { yield bytes }
  let last
  // Same options as hashV1, plus the two layout knobs.
  for await (const { cid } of importer([{ content: once() }], new MemoryBlockstore(), {
    cidVersion: 1,
    rawLeaves: true,
    chunker: fixedSize({ chunkSize }),
    layout: balanced({ maxChildrenPerNode })
  })) last = cid
  return `${last}`
}

// Self-check: with the default layout passed explicitly this must agree with hashV1.
const check = mod251(1000000)
if (await hashWithLayout(check, 262144, 174) !== await hashV1(check)) {
  throw new Error('the bundled importer with explicit defaults disagrees with hashV1')
}

console.log('\n# 2. same importer, mod251(size), other chunk size / fan-out')
const layoutCases = [
  // [chunk size, fan-out, sizes]
  [4, 3, [0, 3, 4, 5, 12, 13, 36, 37, 108, 109, 400, 1001]],
  [1, 2, [2, 3, 5, 8, 17]],
  // Real fan-out with 1-byte chunks: 174 * 174 + 1 leaves give a three-level tree.
  [1, 174, [174, 175, 174 * 174, 174 * 174 + 1]]
]
for (const [chunkSize, fanOut, sizes] of layoutCases) {
  for (const size of sizes) {
    const label = `chunk ${chunkSize} fan-out ${fanOut}`
    console.log(`${label.padEnd(42)} ${String(size).padStart(9)}  ${await hashWithLayout(mod251(size), chunkSize, fanOut)}`)
  }
}
