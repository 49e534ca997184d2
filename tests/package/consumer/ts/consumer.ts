// A TypeScript consumer of the entries' .d.ts, checked with tsc --noEmit --strict. The
// expected errors below fail the check if the types ever let those mistakes through (or are
// missing: an `any` accepts everything).
import { AnimationMixer, Object3D, Quaternion } from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { createSpringBones, SpringBonesError, type CreatorTools, type Rig, type SpringBones, type ValidationError } from 'springbones';
import { createSpringBones as createInlined } from 'springbones/inline';
import {
  SpringBonesGroup, SpringBonesLoaderPlugin, springBonesOf, type SpringBonesAttachment, type SpringBonesWearable, type StaticHairWarning,
} from 'springbones/three';

export async function preview(avatar: Object3D, url: string, entity: object): Promise<() => void> {
  const sb: SpringBones = await createSpringBones();
  const version: string = sb.version;
  const loader = new GLTFLoader();
  const reasons: StaticHairWarning[] = [];
  loader.register((parser) => new SpringBonesLoaderPlugin(parser,
    { sb, springBones: null, entity, bodyShape: 'BaseMale', onWarning: (w) => reasons.push(w) }));
  const gltf = await loader.loadAsync(url);
  const found: SpringBonesWearable | null = springBonesOf(gltf);  // gltf.userData.springBones, typed
  if (found === null) throw new Error('loaded without the plugin');
  const wearable = found;
  const rig: Rig = wearable.rig;
  const worn: SpringBonesAttachment = wearable.wear(avatar, { instance: { integrator: 'xpbd' } });
  const group = new SpringBonesGroup(sb);
  group.add(worn);
  const mixer = new AnimationMixer(avatar);
  const q: Quaternion | undefined = worn.jointObjects[0]?.quaternion;
  console.log(version, rig.joints.length, q?.w, wearable.warnings.map((w) => w.code));
  // An attachment's warnings: a node without an object, or a reason the hair stays at rest (with its fix).
  const fixes: string[] = [];
  for (const w of worn.warnings) if (w.code !== 'node-not-found') fixes.push(w.fix);
  console.log(fixes, reasons.map((r) => r.path));

  // Without sb the plugin starts the page's module at the first wear(); an sb that is not the module is an error.
  new SpringBonesLoaderPlugin(loader as never, { springBones: null });
  // @ts-expect-error a misspelt method of the attachment (springBonesOf's type, not userData's any)
  worn.updat(1 / 60);
  // @ts-expect-error parameters are numbers, not the text of one
  new SpringBonesLoaderPlugin(loader as never, { springBones: { version: 1, models: { h: { SpringBone_a: { stiffness: '1.2' } } } }, contentHash: 'h' });
  // @ts-expect-error the live edit's parameters are numbers too
  wearable.updateParams({ SpringBone_a: { stiffness: '1.2', isRoot: true } });
  wearable.updateParams({ SpringBone_a: { stiffness: 1.2, isRoot: true } });
  // Colliders at run time: on a name or any Object3D; 'dcl-body' resized; the instance's warnings back.
  const colliderWarnings: readonly { code: string }[] = worn.setColliders([{ node: worn.avatarRoot, radius: 0.1 }, { node: 'Avatar_Head', radius: 0.12 }]);
  worn.setColliders('dcl-body', { scale: 0.5, omit: ['left-upper-arm'] });
  console.log(colliderWarnings.length);
  // @ts-expect-error a collider's node is a name or an Object3D
  worn.setColliders([{ node: 3, radius: 0.1 }]);
  // @ts-expect-error omit takes the body's shape names
  worn.setColliders('dcl-body', { omit: ['left-knee'] });
  // @ts-expect-error sb is the springbones module or a promise of it
  new SpringBonesLoaderPlugin(loader as never, { sb: 42, springBones: null });
  // @ts-expect-error rotations are read-only typed arrays of numbers, not strings
  const wrong: string = worn.instance.rotations[0];
  // @ts-expect-error version is read-only
  sb.version = '1.0.0';
  // The creator tools are a second module, loaded on first use; springbones/inline has the same API.
  const tools: CreatorTools = await sb.creatorTools();
  const errors: ValidationError[] = tools.validateSpringBones(entity);
  const inlined: SpringBones = await createInlined();
  console.log(errors.length, inlined.version);
  // @ts-expect-error validation is a creator tool, not a method of the runtime
  sb.validateSpringBones(entity);
  console.log(wrong);

  return () => {
    try {
      mixer.update(1 / 60);
      avatar.updateMatrixWorld();
      group.update(1 / 60);
    } catch (error) {
      if (error instanceof SpringBonesError) console.log(error.code, error.path);
    }
  };
}
