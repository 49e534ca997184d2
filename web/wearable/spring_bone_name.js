// The one JavaScript home of the rule that makes a glTF node a spring-bone candidate: its name
// contains "springbone", with the 26 ASCII letters compared without case and no other character
// folded. The core's discovery (isSpringBoneName in src/loading/rig_builder.cpp) applies the same
// rule, and tests/adapters/spring_bone_name.test.mjs holds the two together on names where a wider
// folding would differ: 'ſpringbone' (U+017F folds to "s" in Unicode), 'SPRİNGBONE' (U+0130
// lower-cases to "i" plus a combining dot), full-width letters.
//
// The three.js adapter, the Babylon drop-in, the diagnostics and the demo's creator panel call
// this; none of them writes the rule again.

const kToken = 'springbone';

/** Lower-cases A-Z only: String.prototype.toLowerCase would fold more than the core does. */
const asciiLower = (text) => text.replace(/[A-Z]/g, (c) => String.fromCharCode(c.charCodeAt(0) + 32));

/** Whether a node of this name is a spring-bone candidate (the core's rule). */
export function isSpringBoneName(name) {
  return typeof name === 'string' && name.length >= kToken.length && asciiLower(name).includes(kToken);
}

/** The names of the spring-bone candidates among glTF nodes ({ name }), in node order. */
export function springBoneNames(nodes) {
  return (Array.isArray(nodes) ? nodes : []).map((node) => node?.name).filter(isSpringBoneName);
}
