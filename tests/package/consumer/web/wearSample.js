// The page both bundles build (Vite: viteEntry.js, esbuild: esbuildEntry.js): a marketplace-style
// preview that loads the sample avatar, loads the hair wearable through the package's GLTFLoader
// plugin with its entity, wears it, walks the avatar for 90 rendered frames and reports on
// window.springbonesResult what the test checks.
import { AnimationMixer, DirectionalLight, PerspectiveCamera, Scene, WebGLRenderer } from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { SpringBonesLoaderPlugin } from 'springbones/three';

export async function wearSample(sb) {
  const entity = await (await fetch('./hair_wearable.entity.json')).json();
  const avatar = await new GLTFLoader().loadAsync('./avatar.glb');

  const loader = new GLTFLoader();
  loader.register((parser) => new SpringBonesLoaderPlugin(parser, {
    sb, springBones: entity.metadata.data.springBones, entity, bodyShape: 'BaseMale' }));
  const wearable = (await loader.loadAsync('./hair_wearable.glb')).userData.springBones;
  const worn = wearable.wear(avatar.scene);

  const scene = new Scene();
  scene.add(avatar.scene, new DirectionalLight(0xffffff, 2));
  const camera = new PerspectiveCamera(35, 1, 0.1, 20);
  camera.position.set(0, 1.5, 3);
  const renderer = new WebGLRenderer();
  renderer.setSize(256, 256);
  document.body.append(renderer.domElement);
  const mixer = new AnimationMixer(avatar.scene);
  mixer.clipAction(avatar.animations.find((clip) => clip.name === 'walk')).play();

  const rest = worn.jointObjects.map((o) => o.quaternion.toArray());
  for (let frame = 0; frame < 90; frame++) {
    mixer.update(1 / 60);
    scene.updateMatrixWorld();
    worn.update(1 / 60);
    renderer.render(scene, camera);
  }
  const now = worn.jointObjects.map((o) => o.quaternion.toArray());
  window.springbonesResult = {
    version: sb.version,
    joints: worn.jointObjects.length,
    warnings: wearable.warnings.length + worn.warnings.length,
    moved: Math.max(...now.flatMap((q, j) => q.map((v, k) => Math.abs(v - rest[j][k])))),
    finite: now.flat().every(Number.isFinite),
  };
}
