// Where a WebAssembly module's bytes go: its code per source file (ours by path, the toolchain's
// libraries by archive) and per function, from a link that keeps the function names. Relinks the
// module's objects as CMake links them (its link.txt) with --profiling-funcs and the linker's map,
// runs the same wasm-opt pass the build runs after the link (kept from the build's own rule, with
// -g so the names survive), and adds up the function bodies of the code section. Prints Markdown
// tables (docs/performance.md, "Every byte", holds the last ones).
//
//   node scripts/benchmarks/size_report.mjs [--module springbones_wasm] [--top 40]     (after scripts/build wasm)
//
// "gzip" of a group is gzip -9 of its bodies laid end to end: how much that code weighs on its
// own, which is not exactly what removing it saves from the whole module (gzip shares repeats
// across groups). The module's own gzip is printed beside it for the whole.
import { execFileSync, execSync } from 'node:child_process';
import { existsSync, mkdtempSync, readdirSync, readFileSync, rmSync, statSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { basename, dirname, join, relative } from 'node:path';
import { fileURLToPath } from 'node:url';
import { gzipSync } from 'node:zlib';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const options = parseArguments(process.argv.slice(2));
const buildDir = join(root, 'build', 'wasm-release', 'wasm');
const targetDir = join(buildDir, 'CMakeFiles', `${options.module}.dir`);
if (!existsSync(join(targetDir, 'link.txt'))) {
  console.error(`size_report: ${relative(root, targetDir)}/link.txt is missing: run scripts/build wasm first`);
  process.exit(1);
}

function parseArguments(args) {
  const parsed = { module: 'springbones_wasm', top: 40 };
  for (let i = 0; i < args.length; i += 2) {
    const [flag, value] = [args[i], args[i + 1]];
    if (flag === '--module' && value) parsed.module = value;
    else if (flag === '--top' && Number.isInteger(Number(value)) && Number(value) > 0) parsed.top = Number(value);
    else {
      console.error('usage: node scripts/benchmarks/size_report.mjs [--module <CMake target, e.g. springbones_wasm>] [--top <functions>]');
      process.exit(2);
    }
  }
  return parsed;
}

// --- The link -----------------------------------------------------------------------------------

/** Relinks the target into `out` with function names and the linker's map; returns the map text. */
function relinkWithNames(out) {
  const linkLine = readFileSync(join(targetDir, 'link.txt'), 'utf8').trim().split('\n')[0];
  const output = linkLine.match(/ -o (\S+)/);
  if (!output) throw new Error(`no -o in ${targetDir}/link.txt`);
  const js = join(out, basename(output[1]));
  const command = linkLine.replace(output[0], ` -o ${js}`) + ' --profiling-funcs -Wl,--print-map';
  // emcc runs its JavaScript tools under Node and needs Debian's acorn (as scripts/build).
  const env = { ...process.env, NODE_PATH: process.env.NODE_PATH ?? '/usr/share/nodejs' };
  const map = execSync(command, { cwd: buildDir, env, encoding: 'utf8', maxBuffer: 1 << 28, stdio: ['ignore', 'pipe', 'inherit'] });
  return { map, wasm: js.replace(/\.js$/, '.wasm') };
}

/** The build's own wasm-opt pass over the linked module (build.make's rule), names kept. */
function optimizeAsTheBuildDoes(wasm) {
  const rules = readFileSync(join(targetDir, 'build.make'), 'utf8');
  const line = rules.split('\n').find((l) => /wasm-opt\S* \S+\.wasm -O/.test(l));
  if (!line) throw new Error(`no wasm-opt rule in ${targetDir}/build.make`);
  const args = line.slice(line.indexOf('wasm-opt')).split(/\s+/);
  const tool = line.slice(0, line.indexOf('wasm-opt') + 'wasm-opt'.length).split(/\s+/).pop();
  const flags = args.slice(2).filter((a, i, all) => a !== '-o' && all[i - 1] !== '-o');
  execFileSync(tool, [wasm, ...flags, '-g', '-o', wasm], { stdio: 'inherit' });
}

// --- The module's sections ----------------------------------------------------------------------

function readU32(bytes, at) {
  let value = 0, shift = 0, byte;
  do {
    byte = bytes[at.offset++];
    value += (byte & 0x7f) * 2 ** shift;
    shift += 7;
  } while (byte & 0x80);
  return value;
}

function readName(bytes, at) {
  const length = readU32(bytes, at);
  const name = new TextDecoder().decode(bytes.subarray(at.offset, at.offset + length));
  at.offset += length;
  return name;
}

/** The code section's function bodies (index, bytes) and the name section's function names. */
function functionsOf(bytes) {
  const at = { offset: 8 };
  let imported = 0;
  const bodies = [];
  const names = new Map();
  while (at.offset < bytes.length) {
    const id = bytes[at.offset++];
    const size = readU32(bytes, at);
    const end = at.offset + size;
    if (id === 2) {  // imports: functions imported take the first indices
      const count = readU32(bytes, at);
      for (let i = 0; i < count; i++) {
        readName(bytes, at);
        readName(bytes, at);
        const kind = bytes[at.offset++];
        if (kind === 0) { readU32(bytes, at); imported++; }
        else if (kind === 1) { at.offset++; const flags = readU32(bytes, at); readU32(bytes, at); if (flags & 1) readU32(bytes, at); }
        else if (kind === 2) { const flags = readU32(bytes, at); readU32(bytes, at); if (flags & 1) readU32(bytes, at); }
        else if (kind === 3) { at.offset += 2; }
        else if (kind === 4) { at.offset++; readU32(bytes, at); }
        else throw new Error(`import kind ${kind} unknown`);
      }
    } else if (id === 10) {
      const count = readU32(bytes, at);
      for (let i = 0; i < count; i++) {
        const length = readU32(bytes, at);
        bodies.push({ index: imported + i, bytes: bytes.subarray(at.offset, at.offset + length) });
        at.offset += length;
      }
    } else if (id === 0 && readName(bytes, at) === 'name') {
      while (at.offset < end) {
        const sub = bytes[at.offset++];
        const subSize = readU32(bytes, at);
        const subEnd = at.offset + subSize;
        if (sub === 1) {
          const count = readU32(bytes, at);
          for (let i = 0; i < count; i++) {
            const index = readU32(bytes, at);
            names.set(index, readName(bytes, at));
          }
        }
        at.offset = subEnd;
      }
    }
    at.offset = end;
  }
  return bodies.map((body) => ({ ...body, name: names.get(body.index) ?? `function ${body.index}` }));
}

// --- Where each function came from ---------------------------------------------------------------

/**
 * Function name -> the input it came from, from the linker's map: in its CODE section every input
 * is a line "<file>:(<section>)" followed by its symbols' names, indented deeper.
 */
function originsOf(map) {
  const origins = new Map();
  let inCode = false, input = null;
  for (const line of map.split('\n')) {
    const columns = line.match(/^\s+(\S+)\s+([0-9a-f]+)\s+([0-9a-f]+)(\s+)(.*)$/);
    if (!columns) continue;
    const [, , , , gap, rest] = columns;
    if (gap.length === 1) {  // an output section
      inCode = rest === 'CODE';
      continue;
    }
    if (!inCode) continue;
    // An input is indented less than its symbols (whose names may hold "::(" themselves).
    const source = gap.length < 16 && rest.match(/^(.*?):\((.*)\)$/);
    if (source) {
      input = source[1];
      origins.set(source[2], input);
    } else if (input) {
      origins.set(rest, input);
    }
  }
  return origins;
}

// Our sources by file name: an archive member is named after its source (instance.cpp.o).
function sourcesByFileName() {
  const byName = new Map();
  const walk = (dir) => {
    for (const entry of readdirSync(dir)) {
      const path = join(dir, entry);
      if (statSync(path).isDirectory()) walk(path);
      else if (/\.(cpp|c)$/.test(entry)) byName.set(entry, [...(byName.get(entry) ?? []), relative(root, path)]);
    }
  };
  for (const dir of ['src', 'wasm']) walk(join(root, dir));
  return byName;
}

/** A readable name for an input of the map: our source file, or the toolchain library it is in. */
function groupOf(input, sources) {
  if (!input) return '(no origin in the map: made by the optimizer)';
  if (input === '<internal>') return '(linker-made)';
  const member = input.match(/([^/]+)\.a\((.*)\)$/);
  if (member && !/springbones/.test(member[1])) {
    // libc-optz, libc++-except...: the library's name without the build variant.
    const library = `lib${member[1].replace(/^lib/, '').replace(/-(optz|except|noexcept|mt)$/, '')}`;
    // printf and strtod are a lever the issue names: their own row inside libc.
    if (library === 'libc' && /printf|fmt|strtod|floatscan|fwrite|frexp/.test(member[2])) return 'libc: number formatting (printf, strtod)';
    return library;
  }
  const object = basename(member ? member[2] : input).replace(/\.o$/, '');
  const candidates = sources.get(object);
  if (candidates?.length === 1) return candidates[0];
  const path = input.match(/\.dir\/(.*)\.o\)?$/);
  return path ? path[1] : object;
}

/** The linker's name of a function wasm-opt renamed: merged copies, duplicates, legalized calls. */
const linkedName = (name) => name.replace(/^byn\$mgfn-shared\$/, '').replace(/^legalfunc\$/, '').replace(/\.\d+$/, '');

// --- The report ---------------------------------------------------------------------------------

const gzip = (chunks) => gzipSync(Buffer.concat(chunks), { level: 9 }).length;
const kb = (bytes) => (bytes / 1024).toFixed(1);

const work = mkdtempSync(join(tmpdir(), 'springbones-size-'));
try {
  const { map, wasm } = relinkWithNames(work);
  optimizeAsTheBuildDoes(wasm);
  const bytes = readFileSync(wasm);
  const functions = functionsOf(bytes);
  const origins = originsOf(map);
  const sources = sourcesByFileName();
  const groups = new Map();
  for (const f of functions) {
    f.group = groupOf(origins.get(linkedName(f.name)), sources);
    const group = groups.get(f.group) ?? { name: f.group, size: 0, count: 0, bodies: [], std: 0 };
    group.size += f.bytes.length;
    if (/^(\S+ )?std::/.test(f.name)) group.std += f.bytes.length;
    group.count++;
    group.bodies.push(f.bytes);
    groups.set(f.group, group);
  }
  const code = functions.reduce((sum, f) => sum + f.bytes.length, 0);
  const shipped = join(root, 'web', 'dist', `${basename(wasm)}`);
  const shippedLine = existsSync(shipped)
    ? `; the shipped ${relative(root, shipped)}: ${readFileSync(shipped).length} bytes, ${gzip([readFileSync(shipped)])} gzip`
    : '';
  console.log(`${options.module}: ${functions.length} functions, ${kb(code)} KB of code (${kb(gzip(functions.map((f) => f.bytes)))} KB gzip) ` +
    `in a module of ${bytes.length} bytes with names${shippedLine}\n`);

  // "of it std::": libc++'s templates, instantiated in that file (the linker keeps the first copy).
  console.log('| source file or library | functions | code KB | of it std:: KB | gzip KB | share of code |');
  console.log('|---|---|---|---|---|---|');
  for (const g of [...groups.values()].sort((a, b) => b.size - a.size)) {
    console.log(`| ${g.name} | ${g.count} | ${kb(g.size)} | ${kb(g.std)} | ${kb(gzip(g.bodies))} | ${(100 * g.size / code).toFixed(1)}% |`);
  }
  const std = functions.filter((f) => /^(\S+ )?std::/.test(f.name));
  console.log(`\nlibc++'s templates (functions named std::...) wherever instantiated: ${std.length} functions, ` +
    `${kb(std.reduce((sum, f) => sum + f.bytes.length, 0))} KB of code (${kb(gzip(std.map((f) => f.bytes)))} KB gzip)`);

  console.log(`\nThe ${options.top} largest functions:\n`);
  console.log('| function | from | bytes |');
  console.log('|---|---|---|');
  for (const f of [...functions].sort((a, b) => b.bytes.length - a.bytes.length).slice(0, options.top)) {
    const name = f.name.length > 110 ? `${f.name.slice(0, 107)}...` : f.name;
    console.log(`| \`${name.replace(/\|/g, '\\|')}\` | ${f.group} | ${f.bytes.length} |`);
  }
} finally {
  rmSync(work, { recursive: true, force: true });
}
