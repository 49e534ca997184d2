// The JavaScript's linter (scripts/test runs `npx eslint .`): ESLint's recommended rules, which
// catch mistakes (undefined names, unused variables, unreachable code) rather than restyle; the
// style the code keeps is written in CONTRIBUTING.md ("Style").
import js from '@eslint/js';
import globals from 'globals';

const kUnderscoreMembers = [
  'PropertyDefinition[key.name=/^_/]',
  'MethodDefinition[key.name=/^_/]',
  'ClassBody MemberExpression[object.type="ThisExpression"][property.name=/^_/]',
];
const kPrivateMessage = 'a private member is a # field or method, not a _ name (CONTRIBUTING.md, "Naming")';

export default [
  // Generated or third-party: Emscripten's glue and the minified bundles, npm's and the builds'.
  { ignores: ['web/dist/**', 'build/**', 'node_modules/**', 'tests/artifacts/**', 'conformance/**/*.json'] },
  js.configs.recommended,
  {
    languageOptions: {
      ecmaVersion: 2022,
      sourceType: 'module',
      // The same files run in browsers and in Node (the API, the adapters, the tests' helpers).
      globals: { ...globals.browser, ...globals.node },
    },
    rules: {
      // Arguments kept for a signature's sake are named with a leading _; a rest sibling leaves keys out on purpose.
      'no-unused-vars': ['error', { argsIgnorePattern: '^_', caughtErrors: 'none', ignoreRestSiblings: true }],
      // A class's private members are # fields and methods (CONTRIBUTING.md, "Naming"): a _ name is
      // public to every caller and to the .d.ts. Only inside classes, so that code patching another
      // library's objects (three-vrm's joints in scripts/lib/) may still reach their _ fields.
      'no-restricted-syntax': ['error', ...kUnderscoreMembers.map((selector) => ({ selector, message: kPrivateMessage }))],
    },
  },
];
