// Cold start with @pixiv/three-vrm-springbone driving the same joints with the same parameters:
// the wearable's data.springBones read as springbones reads it (README "Behaviour in brief": a
// root entry's node and all its descendants, each joint's first child its tail, leaves not
// simulated, a node's own entry else its nearest ancestor's), each joint a VRMSpringBoneJoint
// with stiffness, gravityPower, gravityDir, dragForce = drag, hitRadius 0 and the entry's center.
// The wearable's scene is added under the avatar as it is (no bone matching: that is not this
// library's job), so its joints sit where the sample puts them: the avatar wearing it is drawable
// at once, and the joints are loaded right after (this library has nothing to wait for).
import { Vector3 } from 'three';
import { coldStart } from './cold_start.mjs';

const DEFAULTS = { stiffness: 2, gravityPower: 0, gravityDir: [0, -1, 0], drag: 0.5 };
const isSpringBone = (name) => /springbone/i.test(name ?? '');

coldStart({
  name: 'three-vrm',
  importLibrary: () => import('@pixiv/three-vrm-springbone'),
  start: () => null,
  wear: (vrm, { avatar, wearable, springBones, contentHash }) => {
    avatar.scene.add(wearable.scene);
    return Promise.resolve().then(() => {
      const t0 = performance.now();
      const manager = load(vrm, { avatar, wearable, springBones, contentHash });
      return { joints: manager.joints.size, step: (dt) => manager.update(dt), loadMs: performance.now() - t0 };
    });
  },
});

/** The joints of the wearable's chains, in one VRMSpringBoneManager. */
function load(vrm, { avatar, wearable, springBones, contentHash }) {
  const entries = springBones.models[contentHash];
  const nodes = wearable.parser.json.nodes;
  const objects = [];
  wearable.scene.traverse((o) => {
    const index = wearable.parser.associations.get(o)?.nodes;
    if (index !== undefined) objects[index] = o;
  });
  avatar.scene.updateMatrixWorld(true);
  const byName = (name) => wearable.scene.getObjectByName(name) ?? avatar.scene.getObjectByName(name) ?? null;
  const manager = new vrm.VRMSpringBoneManager();
  const inChain = new Set();  // a root inside another root's chain is simulated once
  const addChain = (index, inherited) => {
    if (inChain.has(index)) return;
    inChain.add(index);
    const children = nodes[index].children ?? [];
    if (children.length === 0) return;
    const params = { ...DEFAULTS, ...(entries[nodes[index].name] ?? inherited) };
    const joint = new vrm.VRMSpringBoneJoint(objects[index], objects[children[0]], {
      stiffness: params.stiffness, gravityPower: params.gravityPower,
      gravityDir: new Vector3().fromArray(params.gravityDir).normalize(), dragForce: params.drag, hitRadius: 0,
    });
    if (params.center) joint.center = byName(params.center);
    manager.addJoint(joint);
    for (const child of children) addChain(child, params);
  };
  nodes.forEach((node, index) => {
    if (isSpringBone(node.name) && entries[node.name]?.isRoot === true) addChain(index, entries[node.name]);
  });
  manager.setInitState();
  return manager;
}
