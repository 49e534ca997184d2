// springbones/inline: the contract of web/inline.js, springbones' own with the runtime module
// inlined. createSpringBones() needs no option; `wasm`, `wasmBinary` or `wasmUrl` load another.
export * from './springbones.js';
