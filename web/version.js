// The package version, as `sb.version` reports it. package.json is the source of truth: this
// copy exists because a browser cannot read package.json next to the module, and
// tests/wasm/package_version.test.mjs and scripts/package fail when the two differ.
export const version = '0.2.0';
