// The Vite app's configuration. `vite build` needs none; the dev server does: it pre-bundles
// dependencies into node_modules/.vite/deps/, where the package's
// new URL('./dist/springbones_wasm.wasm', import.meta.url) no longer finds the .wasm. Serving
// springbones from its own folder keeps the module next to its .wasm.
export default {
  optimizeDeps: { exclude: ['springbones'] },
};
