#!/usr/bin/env node
// springbones command line: look at a wearable's spring bones and simulate them headless, through
// the same WebAssembly module and JS API as the browser (the package's own `springbones` entry; in
// this repository build it first with scripts/build wasm); check an entity before deploying it and
// compute content hashes. Installed, it is the package's `bin`: `npx springbones <command>`. Its
// file name is not the library's (web/springbones.js), so a stack trace never confuses the two.
//
//   springbones inspect <glb> [--metadata f.json] [--hash H | --body-shape S] [--json]
//   springbones simulate <glb> --metadata f.json [--hash H | --body-shape S]
//                                [--frames N] [--fps F] [--drive rest|sway] [--step-hz H] [--max-substeps N]
//                                [--integrator vrm|xpbd]
//   (a VRM avatar as <glb> brings its own spring bones: no --metadata, --hash, --body-shape; what a
//   file is comes from its content, whatever its name ends in)
//   springbones validate <entity.json> [--json]
//   springbones hash <file>
//
// Exit codes: 0 success (validate: the entity is valid), 1 the input could not be loaded (file
// missing, bad GLB or metadata) or, for validate, the entity would be rejected, 2 usage error.
// Commands live in one table below; adding one is adding an entry.
import { realpathSync } from 'node:fs';
import { open } from 'node:fs/promises';
import { basename } from 'node:path';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';

import { swayDrivers } from './sway.mjs';

// The package by its own name (Node resolves a package's self-reference through its exports): the
// minified library that ships, in the repository and installed alike. This process is ours, so
// its stack traces go through the library's source maps (web/*.js); a map is read when its module
// loads, hence the import after turning them on.
const isMain = Boolean(process.argv[1]) && fileURLToPath(import.meta.url) === realpathSync(process.argv[1]);
if (isMain) process.setSourceMapsEnabled?.(true);
const { createSpringBones, SpringBonesError } = await import('springbones');

class UsageError extends Error {}
class LoadError extends Error {}

const kMetadataOptions = {
  metadata: { type: 'string' },
  hash: { type: 'string' },
  'body-shape': { type: 'string' },
};

const commands = {
  inspect: {
    synopsis: 'inspect <glb> [--metadata f.json] [--hash H | --body-shape S] [--json]',
    summary: 'print the chains, drivers and warnings of a wearable or a VRM avatar',
    options: { ...kMetadataOptions, json: { type: 'boolean' } },
    positionals: ['glb'],
    run: inspect,
  },
  simulate: {
    synopsis: 'simulate <glb> --metadata f.json (none for a VRM) [--hash H | --body-shape S] [--frames N] [--fps F]\n' +
              '           [--drive rest|sway] [--step-hz H] [--max-substeps N] [--integrator vrm|xpbd]',
    summary: 'step a wearable or a VRM avatar and print each frame\'s joint rotations as JSON lines',
    options: {
      ...kMetadataOptions,
      frames: { type: 'string', default: '60' },
      fps: { type: 'string', default: '60' },
      drive: { type: 'string', default: 'rest' },
      'step-hz': { type: 'string' },
      'max-substeps': { type: 'string' },
      integrator: { type: 'string' },
    },
    positionals: ['glb'],
    run: simulate,
  },
  validate: {
    synopsis: 'validate <entity.json> [--json]',
    summary: 'list the errors a catalyst would answer for the entity\'s springBones (exit 1 if any)',
    options: { json: { type: 'boolean' } },
    positionals: ['entity'],
    run: validate,
  },
  hash: {
    synopsis: 'hash <file>',
    summary: 'print the Decentraland content hash (CIDv1) of a file',
    options: {},
    positionals: ['file'],
    run: hash,
  },
};

const kUsage = `usage: springbones <command> [arguments]   (npx springbones, or node bin/springbones-cli.mjs)

commands:
${Object.entries(commands).map(([name, c]) => `  ${name.padEnd(9)} ${c.summary}`).join('\n')}

${Object.values(commands).map((c) => `  ${c.synopsis}`).join('\n')}

  <glb>              a glTF file (binary or JSON text, any name): a wearable, whose spring bones
                     come from --metadata, or a VRM avatar (VRMC_springBone or VRM 0.x
                     secondaryAnimation), which carries its own (no --metadata, --hash or
                     --body-shape); the file's content decides which, not its extension
  --metadata f.json  data.springBones, either the object itself or a wearable / entity / Builder
                     item JSON that contains it (metadata.data.springBones or data.springBones)
  --hash H           the springBones.models key to use (default: the GLB's content hash)
  --body-shape S     with an entity metadata file: use the main file hash of the representation
                     worn by body shape S (a URN, or its last segment such as BaseMale)
  --json             inspect: print the rig as JSON instead of text
  --frames N         simulate: frames to run (default 60)
  --fps F            simulate: frame rate; each frame steps by 1/F seconds (default 60)
  --drive rest|sway  simulate: keep the drivers at rest (default), or sway the whole avatar so the
                     chains move (bin/sway.mjs)
  --step-hz H        simulate: fixed simulation rate, 1..1000 (default 60; 120 with xpbd)
  --max-substeps N   simulate: steps per frame at most, 1..64 (default 4; 8 with xpbd)
  --integrator I     simulate: vrm (default) or xpbd (default rate 120 Hz)
  <entity.json>      validate: a catalyst entity {content, metadata: {data}} or a Builder item
                     {contents, data}, with data.representations and data.springBones
  --json             validate: print {valid, errors: [{path, message}]} as JSON

exit codes: 0 ok (validate: valid), 1 input could not be loaded (validate: invalid), 2 usage error
`;

// ---------------------------------------------------------------------------------------------
// Commands

async function inspect({ glb, values }, out, err) {
  const sb = await createSpringBones();
  const { rig, source } = await loadModel(sb, glb, values, { needsSprings: false, err });
  if (values.json) {
    const data = {
      file: glb, format: rig.format, contentHash: rig.contentHash, hashSource: source, nodeCount: rig.nodeCount,
      chains: rig.chains, joints: rig.joints, drivers: rig.drivers, colliders: rig.colliders, warnings: rig.warnings,
    };
    out.write(JSON.stringify(data, null, 2) + '\n');
    return;
  }
  const lines = [];
  lines.push(`${basename(glb)}: ${rig.nodeCount} nodes, ${rig.joints.length} simulated joints`);
  lines.push(rig.format === 'dcl' ? `models key: ${rig.contentHash} (${source})` : `springs: ${source}`);
  lines.push(`chains (${rig.chains.length}):`);
  for (const root of rig.chains) {
    const members = rig.joints.filter((j) => j.chain === root);
    const parent = rig.joints[root].parentDriver >= 0 ? rig.drivers[rig.joints[root].parentDriver].name : '(scene root)';
    lines.push(`  ${rig.joints[root].name}: ${members.length} joint${members.length === 1 ? '' : 's'}, under ${parent}`);
    for (const j of members) {
      const depth = depthOf(rig.joints, j);
      const p = j.params;
      const center = j.centerDriver >= 0 ? `, center ${rig.drivers[j.centerDriver].name}` : '';
      lines.push(`    ${'  '.repeat(depth)}${j.name} -> ${j.tail ?? '(virtual tail)'}  stiffness ${p.stiffness}, gravityPower ` +
                 `${p.gravityPower}, gravityDir [${p.gravityDir.join(', ')}], drag ${p.drag}${center}`);
    }
  }
  lines.push(`drivers (${rig.drivers.length}): ${rig.drivers.map((d) => d.name).join(', ') || '-'}`);
  if (rig.colliders.length > 0) {
    lines.push(`colliders (${rig.colliders.length}):`);
    for (const c of rig.colliders) {
      const size = c.shape === 'plane' ? `normal [${c.normal.join(', ')}]` : `radius ${c.radius}`;
      lines.push(`  ${c.inside ? 'inside ' : ''}${c.shape} on ${c.node}: offset [${c.offset.join(', ')}]` +
                 `${c.tail ? `, tail [${c.tail.join(', ')}]` : ''}, ${size}`);
    }
  }
  lines.push(`warnings (${rig.warnings.length}):`);
  for (const w of rig.warnings) lines.push(`  ${w.code}${w.path ? ` at ${w.path}` : ''}: ${w.message}`);
  out.write(lines.join('\n') + '\n');
}

async function simulate({ glb, values }, out, err) {
  const frames = parseNumber('--frames', values.frames, { integer: true, min: 0 });
  const fps = parseNumber('--fps', values.fps, { positive: true });
  // A rate so small that its frame time is not a number (5e-324: 1/F is Infinity) has no frames.
  if (!Number.isFinite(1 / fps)) throw new UsageError(`--fps ${values.fps} gives a frame time of ${1 / fps} s`);
  if (values.drive !== 'rest' && values.drive !== 'sway') {
    throw new UsageError(`--drive must be rest or sway, not '${values.drive}'`);
  }
  const instanceOptions = {};
  if (values['step-hz'] !== undefined) {
    instanceOptions.stepHz = parseNumber('--step-hz', values['step-hz'], { min: 1, max: 1000 });
  }
  if (values['max-substeps'] !== undefined) {
    instanceOptions.maxSubsteps = parseNumber('--max-substeps', values['max-substeps'], { integer: true, min: 1, max: 64 });
  }
  if (values.integrator !== undefined) {
    if (values.integrator !== 'vrm' && values.integrator !== 'xpbd') {
      throw new UsageError(`--integrator must be vrm or xpbd, not '${values.integrator}'`);
    }
    instanceOptions.integrator = values.integrator;
  }
  const sb = await createSpringBones();
  const { rig } = await loadModel(sb, glb, values, { needsSprings: true, err });
  const instance = rig.createInstance(instanceOptions);
  const rest = Float32Array.from(instance.driverMatrices);
  const scratch = new Float64Array(16);
  const dt = 1 / fps;
  let chunk = '';
  for (let k = 1; k <= frames; ++k) {
    const t = k / fps;
    if (values.drive === 'sway') swayDrivers(rest, instance.driverMatrices, t, scratch);
    instance.step(dt);
    chunk += `{"frame":${k},"t":${t},"rotations":[${instance.rotations.join(',')}]}\n`;
    if (chunk.length > 1 << 16) {
      await write(out, chunk);
      chunk = '';
    }
  }
  await write(out, chunk);
}

// Exit code 1 when the catalyst would reject the entity: the errors are the command's answer.
async function validate({ entity: path, values }, out) {
  const text = utf8Text(path, await readInput(path, kMaxJsonFileBytes));
  let entity;
  try {
    entity = JSON.parse(text);
  } catch (error) {
    throw new LoadError(`${path}: not JSON (${error.message})`);
  }
  if (entity === null || typeof entity !== 'object') entity = [];  // refused below, as an array is
  const tools = await (await createSpringBones()).creatorTools();
  let errors;
  try {
    errors = tools.validateSpringBones(entity);
  } catch (error) {
    if (!(error instanceof SpringBonesError) || error.code !== 'invalid-argument') throw error;
    throw new LoadError(`${path}: not an entity or item (${error.message}; the models keys are checked against ` +
                        'the representations\' main files)');
  }
  if (values.json) {
    out.write(JSON.stringify({ file: path, valid: errors.length === 0, errors }, null, 2) + '\n');
  } else if (errors.length === 0) {
    out.write(`${path}: valid\n`);
  } else {
    const lines = [`${path}: ${errors.length} error${errors.length === 1 ? '' : 's'}`];
    for (const e of errors) lines.push(`  ${e.path || '(springBones)'}: ${withoutPath(e)}`);
    out.write(lines.join('\n') + '\n');
  }
  return errors.length === 0 ? 0 : 1;
}

async function hash({ file }, out) {
  const bytes = await readInput(file);
  const sb = await createSpringBones();
  out.write(`${sb.contentHash(bytes)}\n`);
}

// ---------------------------------------------------------------------------------------------
// Loading

// A file is a VRM avatar when it carries a VRM spring-bone extension, whatever its name: the
// module's VRM reader answers format 'none' for a glTF with neither extension, and such a file is
// a wearable, whose spring bones come from its metadata. A file the glTF reader rejects gets the
// same error from either loader, so the VRM reader's answer is the one reported.
async function loadModel(sb, path, values, { needsSprings, err }) {
  if (values.hash !== undefined && values['body-shape'] !== undefined) {
    throw new UsageError('give --hash or --body-shape, not both');
  }
  const bytes = await readInput(path);
  const vrm = loadOrExplain(path, () => sb.loadVrm(bytes));
  if (vrm.format !== 'none') {
    for (const option of ['metadata', 'hash', 'body-shape']) {
      if (values[option] !== undefined) {
        vrm.dispose();
        throw new UsageError(`--${option} does not apply to a VRM avatar: ${basename(path)} carries its own spring ` +
                             `bones (${kVrmFormatNames[vrm.format] ?? vrm.format})`);
      }
    }
    return { rig: vrm, source: `VRM, ${vrm.format}` };
  }
  vrm.dispose();
  const notes = [];
  if (/\.vrm$/i.test(path)) {
    notes.push(`${basename(path)} has no VRM spring bones (neither VRMC_springBone nor VRM 0.x secondaryAnimation): ` +
               'read as a wearable');
  }
  if (values.metadata === undefined) {
    const hint = 'no springBones metadata given: pass --metadata (a wearable\'s spring bones are in its ' +
                 'data.springBones, not in the GLB)';
    if (needsSprings) throw new UsageError([...notes, hint].join('; '));
    notes.push(hint);
  }
  for (const note of notes) err.write(`springbones: note: ${note}\n`);
  return loadWearable(sb, path, bytes, values);
}

const kVrmFormatNames = { 'vrmc-springbone': 'VRMC_springBone', vrm0: 'VRM 0.x secondaryAnimation' };

async function loadWearable(sb, glbPath, glb, values) {
  let springBones = null;
  let entity;
  if (values.metadata !== undefined) {
    const text = utf8Text(values.metadata, await readInput(values.metadata, kMaxJsonFileBytes));
    let json;
    try {
      json = JSON.parse(text);
    } catch (error) {
      throw new LoadError(`${values.metadata}: not JSON (${error.message})`);
    }
    ({ springBones, entity } = splitMetadata(json));
  }
  let options = {};
  let source = 'computed from the GLB';
  if (values.hash !== undefined) {
    options = { contentHash: values.hash };
    source = 'given with --hash';
  } else if (values['body-shape'] !== undefined) {
    if (entity === undefined) {
      throw new UsageError('--body-shape needs a --metadata file that is an entity or item (with representations)');
    }
    options = { entity, bodyShape: values['body-shape'] };
    source = `main file of ${values['body-shape']} in the entity`;
  }
  return { rig: loadOrExplain(glbPath, () => sb.loadRig(glb, springBones, options)), source };
}

// The module's errors name no file: the message says which one failed to load.
function loadOrExplain(path, load) {
  try {
    return load();
  } catch (error) {
    if (error instanceof SpringBonesError) {
      throw new LoadError(`${path}: ${error.code}: ${error.message}${error.path ? ` (at ${error.path})` : ''}`);
    }
    throw error;
  }
}

/**
 * A metadata file is either data.springBones itself or a document holding it: a catalyst entity
 * (metadata.data.springBones), a wearable's metadata or a Builder item (data.springBones).
 */
export function splitMetadata(json) {
  if (json === null || typeof json !== 'object' || Array.isArray(json)) {
    return { springBones: json, entity: undefined };
  }
  const data = json.metadata?.data ?? json.data;
  if (data !== null && typeof data === 'object' && !('models' in json)) {
    return { springBones: data.springBones ?? null, entity: json };
  }
  return { springBones: json, entity: undefined };
}

// The bounds of what the commands read: a GLB holds its buffers (meshes, textures), a metadata or
// entity file is JSON text, which the library takes up to its limit of springBones text.
const kMaxModelFileBytes = 1 << 30;
const kMaxJsonFileBytes = 16 << 20;

// A file's bytes: a regular file (not a device, a pipe or a folder, which could be read without
// end) of at most `maxBytes`, checked on the opened file before anything is read.
async function readInput(path, maxBytes = kMaxModelFileBytes) {
  let handle;
  try {
    handle = await open(path, 'r');
  } catch (error) {
    throw new LoadError(`cannot read ${path}: ${error.code ?? error.message}`);
  }
  try {
    const stats = await handle.stat();
    if (!stats.isFile()) throw new LoadError(`cannot read ${path}: not a regular file`);
    if (stats.size > maxBytes) {
      throw new LoadError(`cannot read ${path}: ${stats.size} bytes, more than the limit of ${maxBytes}`);
    }
    // One byte more than the size: a file that grew since stat is refused, not read without end.
    const bytes = Buffer.alloc(stats.size + 1);
    let length = 0;
    for (;;) {
      const { bytesRead } = await handle.read(bytes, length, bytes.length - length, null);
      if (bytesRead === 0) break;
      length += bytesRead;
      if (length > stats.size) throw new LoadError(`cannot read ${path}: it grows while it is read`);
    }
    return bytes.subarray(0, length);
  } catch (error) {
    if (error instanceof LoadError) throw error;
    throw new LoadError(`cannot read ${path}: ${error.code ?? error.message}`);
  } finally {
    await handle.close();
  }
}

// A JSON file's text: bytes that are not UTF-8 are refused, rather than read with U+FFFD in their
// place (a name the file does not hold).
function utf8Text(path, bytes) {
  try {
    return new TextDecoder('utf-8', { fatal: true }).decode(bytes);
  } catch {
    throw new LoadError(`${path}: not UTF-8 (an invalid byte at offset ${firstInvalidUtf8(bytes)})`);
  }
}

// Where UTF-8 decoding fails (RFC 3629: no overlongs, no surrogates, nothing past U+10FFFF).
function firstInvalidUtf8(bytes) {
  for (let i = 0; i < bytes.length;) {
    const b = bytes[i];
    const [length, low, high] = b < 0x80 ? [1] : b >= 0xc2 && b <= 0xdf ? [2, 0x80, 0xbf]
      : b === 0xe0 ? [3, 0xa0, 0xbf] : b === 0xed ? [3, 0x80, 0x9f] : b >= 0xe1 && b <= 0xef ? [3, 0x80, 0xbf]
        : b === 0xf0 ? [4, 0x90, 0xbf] : b >= 0xf1 && b <= 0xf3 ? [4, 0x80, 0xbf] : b === 0xf4 ? [4, 0x80, 0x8f] : [0];
    if (length === 0) return i;
    for (let k = 1; k < length; ++k) {
      const c = bytes[i + k];
      if (c === undefined || c < (k === 1 ? low : 0x80) || c > (k === 1 ? high : 0xbf)) return i;
    }
    i += length;
  }
  return bytes.length;
}

// A validation message without the path the line already starts with: the creator tools write
// each message as the validator does, "springBones<path> must ...".
function withoutPath({ path, message }) {
  const prefix = `springBones${path} `;
  return path && message.startsWith(prefix) ? message.slice(prefix.length) : message;
}

// ---------------------------------------------------------------------------------------------
// Plumbing

function depthOf(joints, joint) {
  let depth = 0;
  for (let j = joint; j.parent >= 0; j = joints[j.parent]) ++depth;
  return depth;
}

function parseNumber(flag, text, { integer = false, min = -Infinity, max = Infinity, positive = false } = {}) {
  const value = Number(text);
  if (text.trim() === '' || !Number.isFinite(value) || (integer && !Number.isInteger(value)) ||
      value < min || value > max || (positive && !(value > 0))) {
    const bounds = [positive ? '> 0' : '', min > -Infinity ? `>= ${min}` : '', max < Infinity ? `<= ${max}` : '']
      .filter(Boolean).join(' and ');
    throw new UsageError(`${flag} must be ${integer ? 'an integer' : 'a number'}${bounds ? ` ${bounds}` : ''}, not '${text}'`);
  }
  return value;
}

// parseArgs's complaint in our words: which option, for which command, and what it takes.
function argumentError(name, command, args, error) {
  const known = Object.keys(command.options).map((o) => `--${o}`);
  const takes = `${name} takes: ${command.synopsis}`;
  const option = args.find((a) => a.startsWith('-') && !known.includes(a.split('=')[0]));
  if (error.code === 'ERR_PARSE_ARGS_UNKNOWN_OPTION' && option !== undefined) {
    const flag = option.split('=')[0];
    const near = known.find((k) => editDistance(k, flag) <= 2);
    return `unknown option '${flag}' for ${name}${near ? ` (did you mean ${near}?)` : ''}; ${takes}`;
  }
  if (error.code === 'ERR_PARSE_ARGS_INVALID_OPTION_VALUE') {
    const flag = known.find((k) => args.includes(k) && command.options[k.slice(2)].type === 'string' &&
                            (args.indexOf(k) === args.length - 1 || args[args.indexOf(k) + 1].startsWith('--')));
    if (flag !== undefined) return `${flag} needs a value; ${takes}`;
    const boolean = known.find((k) => command.options[k.slice(2)].type === 'boolean' &&
                               args.some((a) => a.startsWith(`${k}=`)));
    if (boolean !== undefined) return `${boolean} takes no value; ${takes}`;
  }
  return `bad arguments for ${name}; ${takes}`;
}

function editDistance(a, b) {
  let row = Array.from({ length: b.length + 1 }, (_, j) => j);
  for (let i = 1; i <= a.length; ++i) {
    const next = [i];
    for (let j = 1; j <= b.length; ++j) {
      next[j] = Math.min(row[j] + 1, next[j - 1] + 1, row[j - 1] + (a[i - 1] === b[j - 1] ? 0 : 1));
    }
    row = next;
  }
  return row[b.length];
}

function write(stream, text) {
  if (text.length === 0) return Promise.resolve();
  return new Promise((resolve) => (stream.write(text) ? resolve() : stream.once('drain', resolve)));
}

export async function main(argv, out = process.stdout, err = process.stderr) {
  const [name, ...rest] = argv;
  if (name === undefined || name === 'help' || name === '--help' || name === '-h') {
    (name === undefined ? err : out).write(kUsage);
    return name === undefined ? 2 : 0;
  }
  const command = Object.hasOwn(commands, name) ? commands[name] : undefined;
  try {
    if (command === undefined) throw new UsageError(`unknown command '${name}'`);
    let parsed;
    try {
      parsed = parseArgs({ args: rest, options: command.options, allowPositionals: true, strict: true });
    } catch (error) {
      throw new UsageError(argumentError(name, command, rest, error));
    }
    const { values, positionals } = parsed;
    if (positionals.length !== command.positionals.length) {
      throw new UsageError(`${name} takes ${command.positionals.map((p) => `<${p}>`).join(' ')}` +
                           (positionals.length ? `, got: ${positionals.join(' ')}` : ''));
    }
    for (const option of command.required ?? []) {
      if (values[option] === undefined) throw new UsageError(`${name} needs --${option}`);
    }
    const named = Object.fromEntries(command.positionals.map((p, i) => [p, positionals[i]]));
    return (await command.run({ ...named, values }, out, err)) ?? 0;
  } catch (error) {
    if (error instanceof UsageError) {
      err.write(`springbones: ${error.message}\n\n${kUsage}`);
      return 2;
    }
    if (error instanceof LoadError || error instanceof SpringBonesError) {
      err.write(`springbones: ${error.message}\n`);
      return 1;
    }
    throw error;
  }
}

if (isMain) {
  // `simulate | head` closes the pipe early: that is not an error.
  process.stdout.on('error', (error) => {
    if (error.code === 'EPIPE') process.exit(0);
    throw error;
  });
  process.exitCode = await main(process.argv.slice(2));
}
