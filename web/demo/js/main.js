// The preview: a three.js scene with the sample avatar (or a crowd of them), each wearing the
// current wearable through the springbones three.js adapter, animated with the avatar's clips.
// Every attachment is in one SpringBonesGroup: one springbones scene.step per frame for all. The
// creator panel (creator.js) decides which wearable and which parameters; this file owns the
// scene, the frame loop, the playback controls (animation, turn, shake, pause, reset, integrator,
// colliders, debug lines, the simulation budget) and the read-only debug hook
// (window.springbonesDemo) the browser test drives.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import * as SkeletonUtils from 'three/addons/utils/SkeletonUtils.js';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
import { createSpringBones } from '../../springbones.js';
import { attachWearable, avatarArmature, avatarRestBones, wearableNodes, SpringBonesGroup, SpringBonesHelper } from '../../three/springBonesThree.js';
import { AVATAR_COLLIDERS, AVATAR_HIT_RADIUS, ColliderHelper } from './colliders.js';
import { Creator } from './creator.js';
import { HairDrag } from './drag.js';
import { RecentFrames } from './readout.js';
import { kShakeSeconds, kSpinSpeed, shakeOffset } from './motion.js';

const $ = (id) => document.getElementById(id);
export const ASSETS = new URL('../assets/', import.meta.url);
// The module's download, started as this file runs (index.html preloads it), in parallel with the
// avatar's; createSpringBones compiles it as it arrives.
const kModuleDownload = fetch(new URL('../../dist/springbones_wasm.wasm', import.meta.url));

const kSpacing = 1.1;         // metres between avatars of a crowd
const kFade = 0.35;           // seconds of cross-fade between clips
const kMaxFrameDt = 0.25;     // longer frames (hidden tab, debugger) are cut for the animation
const kMaxDemoWind = 3;       // the wind slider's end: hair blown well back, not flat
const kShakeScratch = { x: 0, y: 0, roll: 0 };  // the frame loop allocates nothing
const kViewerScratch = new THREE.Vector3();      // the camera's world position, for the budget
// Camera presets: the whole avatar, or head and shoulders (the earrings are 3 cm long). Both look
// from the avatar's right, about 60 degrees off its front, so that the ponytail, which hangs from
// the back of the head, shows beside the head rather than behind it (tests/browser/view.test.mjs).
const kViews = {
  body: { position: [3.45, 1.55, 1.85], target: [0, 1.0, 0] },
  head: { position: [1.1, 1.63, 0.75], target: [0, 1.55, 0] },
};

class Preview {
  constructor() {
    this.sb = null;
    this.avatarGltf = null;
    this.avatars = [];         // { holder, root, body, mixer, actions, attachment, helper }
    this.wearable = null;      // { gltf, rig, label }
    this.animation = 'walk';
    this.paused = false;
    this.yaw = 0;              // degrees
    this.spin = false;
    this.shakeTime = -1;       // seconds since the shake started, -1 when not shaking
    this.showChains = false;
    this.showBody = true;
    this.integrator = 'vrm';
    this.colliders = true;     // the avatar's head and torso colliders go into the rig
    this.showColliders = false;
    this.headSphere = null;    // the body colliders' head sphere (headClearance)
    this.wind = 0;             // the wind slider's strength, world units per second
    this.inertia = 1;          // the inertia slider: how much of the avatar's motion the hair feels
    this.bodyScale = 1;        // the body colliders slider: the 'dcl-body' shapes' radii times this
    this.budget = null;        // simulate only this many avatars nearest to the camera; null: all
    this.onRigOptionsChange = null;  // set by the creator: rebuild the rig
    this.springFrames = new RecentFrames(1000);  // ms per frame in group.update (drivers, scene.step, rotations)
    this.lastSubsteps = null;  // the most fixed steps an avatar took in the last frame, null before one
    this.lastDt = NaN;
    this.frameTimes = new Float64Array(120);
    this.frameCount = 0;
    this.lastReadout = 0;
  }

  async init() {
    const canvas = $('view');
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    this.renderer.toneMapping = THREE.NeutralToneMapping;
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x23262e);
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.05, 100);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.enableDamping = true;
    this.setView('body');
    // A press on a chain's tail drags the hair (instance.grab); elsewhere it orbits.
    this.drag = new HairDrag(canvas, this.camera, () => this.avatars.map((a) => a.attachment).filter(Boolean));

    // Image-based light for the metals, plus a key light.
    const pmrem = new THREE.PMREMGenerator(this.renderer);
    this.scene.environment = pmrem.fromScene(new RoomEnvironment(), 0.04).texture;
    this.scene.environmentIntensity = 0.8;
    pmrem.dispose();
    this.scene.add(new THREE.HemisphereLight(0xdde6ff, 0x3a3430, 0.8));
    const sun = new THREE.DirectionalLight(0xffffff, 2.2);
    sun.position.set(2, 4, 3);
    this.scene.add(sun);
    const ground = new THREE.Mesh(new THREE.CircleGeometry(4, 64), new THREE.MeshStandardMaterial({ color: 0x2e323c, roughness: 1 }));
    ground.rotation.x = -Math.PI / 2;
    this.scene.add(ground);
    const grid = new THREE.GridHelper(8, 16, 0x4a5060, 0x3a3f4c);
    grid.position.y = 0.001;
    this.scene.add(grid);

    // The canvas's own box: in a narrow page (a marketplace iframe) the readout sits under it.
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();

    this.loader = new GLTFLoader();
    const avatarDownload = fetchBytes(new URL('avatar.glb', ASSETS));
    // The module starts while the avatar downloads and is drawn: only the springs wait for it.
    const springBones = createSpringBones({ wasm: kModuleDownload });
    springBones.catch(() => {});  // reported by the await below, once the avatar is up
    const avatarBytes = await avatarDownload;
    this.avatarGltf = await this.loader.parseAsync(avatarBytes.buffer, ASSETS.href);
    this.timer = new THREE.Timer();
    this.timer.connect(document);  // a hidden tab's pause does not come back as one long frame
    this.setAvatarCount(1);
    this.renderer.setAnimationLoop((timestamp) => this.frame(timestamp));
    this.sb = await springBones;
    this.group = new SpringBonesGroup(this.sb);  // every attachment, stepped by one scene.step
    performance.mark('springbones-ready');
  }

  resize() {
    const canvas = this.renderer.domElement;
    const w = Math.max(1, canvas.clientWidth);
    const h = Math.max(1, canvas.clientHeight);
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  // ---- avatars

  setAvatarCount(n) {
    n = Math.max(1, Math.min(100, Math.floor(n) || 1));
    while (this.avatars.length > n) this.removeAvatar(this.avatars.pop());
    while (this.avatars.length < n) this.avatars.push(this.createAvatar(this.avatars.length));
    const cols = Math.ceil(Math.sqrt(n));
    this.avatars.forEach((a, i) => {
      const col = i % cols;
      const row = Math.floor(i / cols);
      a.base.set((col - (cols - 1) / 2) * kSpacing, 0, -row * kSpacing);
    });
    this.placeAvatars();
  }

  createAvatar(index) {
    const root = SkeletonUtils.clone(this.avatarGltf.scene);
    const holder = new THREE.Group();  // carries the turn and the shake, so the springs feel them
    holder.name = `avatar_${index}`;
    holder.add(root);
    this.scene.add(holder);
    let body = null;
    root.traverse((o) => { if (o.isSkinnedMesh && !body) body = o; });
    if (body) body.visible = this.showBody;
    const mixer = new THREE.AnimationMixer(root);
    const actions = {};
    for (const clip of this.avatarGltf.animations) actions[clip.name] = mixer.clipAction(clip);
    const avatar = {
      holder, root, body, mixer, actions, base: new THREE.Vector3(),
      attachment: null, helper: null, colliderHelper: null, wearableRoot: null, extraDrivers: [],
    };
    // a crowd does not march in step
    const action = actions[this.animation];
    if (action) {
      action.play();
      mixer.setTime(index * 0.37);
    }
    if (this.wearable) this.wear(avatar);
    return avatar;
  }

  removeAvatar(avatar) {
    this.unwear(avatar);
    avatar.mixer.stopAllAction();
    avatar.holder.removeFromParent();
  }

  placeAvatars() {
    const shake = this.shakeOffset();
    for (const a of this.avatars) {
      a.holder.position.set(a.base.x + shake.x, a.base.y + shake.y, a.base.z);
      a.holder.rotation.set(0, THREE.MathUtils.degToRad(this.yaw), shake.roll);
    }
  }

  /** A decaying side-to-side jolt (metres, radians), written into a scratch object. */
  shakeOffset() {
    return shakeOffset(this.shakeTime, kShakeScratch);
  }

  // ---- wearable

  /** Replaces the worn item on every avatar. `gltf` is kept pristine: avatars wear clones. */
  setWearable(gltf, rig, label) {
    const old = this.wearable;
    for (const a of this.avatars) this.unwear(a);
    if (old) {
      old.rig.dispose();
      disposeGltf(old.gltf);
    }
    // Why the hair would stay at rest (the adapter's warnings): said once per wearable, not once
    // per avatar of the crowd; the creator panel lists them too.
    const said = new Set();
    const onWarning = (w) => {
      if (said.has(w.code)) return;
      said.add(w.code);
      console.warn(`springbones demo [${w.code}] ${label}: ${w.message} Fix: ${w.fix}`);
    };
    this.wearable = { gltf, rig, label, onWarning };
    for (const a of this.avatars) this.wear(a);
    this.restartReadout();
  }

  /** Same GLB, new parameters: every attachment switches to the new rig (shared by all). */
  setRig(rig) {
    const old = this.wearable.rig;
    this.wearable.rig = rig;
    for (const a of this.avatars) {
      if (!a.attachment) continue;
      a.attachment.setRig(rig);  // disposes of the old instance, which leaves the scene with it
      this.applyBodyScale(a);
      this.linkAttachment(a);
      a.helper.rebuild();
    }
    old.dispose();
    this.restartReadout();  // new instances: other costs, and their step clocks start at zero
  }

  /**
   * loadRig options the preview adds to the wearable's metadata: the avatar's colliders, measured
   * on the avatar's bones (every avatar of the crowd is a clone of the one file: one rig serves all).
   */
  rigOptions() {
    if (!this.colliders) return {};
    return { colliders: AVATAR_COLLIDERS, hitRadius: AVATAR_HIT_RADIUS, avatarBones: avatarRestBones(this.avatarGltf.scene) };
  }

  wear(avatar) {
    const { gltf, rig, onWarning } = this.wearable;
    const clone = SkeletonUtils.clone(gltf.scene);
    avatar.attachment = attachWearable(avatar.root, clone, rig, {
      nodes: wearableNodes(gltf, clone), instance: { integrator: this.integrator, inertia: this.inertia }, onWarning,
      mixer: avatar.mixer,  // a clip starting is a jump: the hair is carried, not whipped
    });
    avatar.wearableRoot = clone;
    avatar.helper = new SpringBonesHelper(avatar.attachment);
    avatar.helper.visible = this.showChains;
    this.scene.add(avatar.helper);
    this.group.add(avatar.attachment);  // setRig keeps it in the group, dispose takes it out
    avatar.bodyScaled = false;
    this.applyBodyScale(avatar);
    this.linkAttachment(avatar);
  }

  /**
   * After attaching or a new rig: drivers the wearable GLB does not have (a collider on an avatar
   * bone, node -1) are found by name in the avatar's armature and written by the frame loop; the
   * colliders are drawn on their bones.
   */
  linkAttachment(avatar) {
    const { attachment } = avatar;
    const armature = avatarArmature(avatar.root);
    avatar.extraDrivers = [];
    attachment.rig.drivers.forEach((d, index) => {
      if (attachment.driverObjects[index]) return;
      const object = armature.get(d.name);
      if (object) avatar.extraDrivers.push({ index, elements: object.matrixWorld.elements });
    });
    const handled = new Set(avatar.extraDrivers.map((d) => attachment.rig.drivers[d.index].name));
    for (const w of attachment.warnings) {
      // The adapter said the static-hair reasons itself (once); a node without an object is the
      // demo's to say, unless it found the avatar's bone of that name above.
      if (w.code === 'node-not-found' && !handled.has(w.message.split(' ')[1])) console.warn(`springbones demo: ${w.message}`);
    }
    // The head sphere of the body colliders, kept for headClearance when they are switched off.
    const head = attachment.rig.colliders.find((c) => c.shape === 'sphere' && c.node === 'Avatar_Head');
    if (head) this.headSphere = head;
    avatar.colliderHelper?.dispose();
    const objectOf = (driver) => attachment.driverObjects[driver] ?? armature.get(attachment.rig.drivers[driver].name) ?? null;
    avatar.colliderHelper = new ColliderHelper(attachment.rig.colliders, objectOf);
    avatar.colliderHelper.setVisible(this.showColliders);
  }

  unwear(avatar) {
    if (!avatar.attachment) return;
    avatar.attachment.dispose();  // takes it out of the group
    avatar.helper.removeFromParent();
    avatar.helper.dispose();
    avatar.colliderHelper?.dispose();
    avatar.attachment = null;
    avatar.helper = null;
    avatar.colliderHelper = null;
    avatar.wearableRoot = null;
    avatar.extraDrivers = [];
  }

  get jointCount() {
    return this.avatars.reduce((n, a) => n + (a.attachment ? a.attachment.jointObjects.length : 0), 0);
  }

  // ---- controls

  setAnimation(name) {
    this.animation = name;
    for (const a of this.avatars) {
      const next = a.actions[name];
      for (const [clipName, action] of Object.entries(a.actions)) {
        if (clipName !== name && action.isRunning()) action.fadeOut(kFade);
      }
      if (next) next.reset().fadeIn(kFade).play();
    }
  }

  /** A camera preset of kViews ('body' or 'head'); the orbit controls start from it. */
  setView(name) {
    const view = kViews[name];
    if (!view) throw new RangeError(`unknown view ${name}`);
    this.camera.position.fromArray(view.position);
    this.controls.target.fromArray(view.target);
    this.controls.update();
    $('view-preset').value = name;
  }

  setPaused(paused) {
    this.paused = paused;
    $('pause').setAttribute('aria-pressed', String(paused));
    $('pause').textContent = paused ? 'Play' : 'Pause';
  }

  setYaw(degrees) {
    this.yaw = THREE.MathUtils.euclideanModulo(degrees + 180, 360) - 180;
    $('turn').value = String(Math.round(this.yaw));
    $('turn-num').value = String(Math.round(this.yaw));
  }

  shake() {
    this.shakeTime = 0;
  }

  /**
   * The springs back to rest, the animation to its start, the avatar facing forward: the hair is
   * settled in the clip's first pose (attachment.settle), so it starts hanging, not falling.
   */
  reset() {
    this.shakeTime = -1;
    this.spin = false;
    $('spin').checked = false;
    this.setYaw(0);
    this.avatars.forEach((a, i) => {
      a.mixer.stopAllAction();
      const action = a.actions[this.animation];
      if (action) action.reset().play();
      a.mixer.setTime(i * 0.37);
    });
    this.placeAvatars();
    this.drag.release();
    this.scene.updateMatrixWorld();
    for (const a of this.avatars) {
      if (!a.attachment) continue;
      this.writeExtraDrivers(a);
      a.attachment.settle();
    }
  }

  setShowChains(show) {
    this.showChains = show;
    for (const a of this.avatars) if (a.helper) a.helper.visible = show;
  }

  setShowBody(show) {
    this.showBody = show;
    for (const a of this.avatars) if (a.body) a.body.visible = show;
  }

  /** 'vrm' or 'xpbd': every avatar gets a new instance of that integrator, starting from rest. */
  setIntegrator(name) {
    if (name !== 'vrm' && name !== 'xpbd') throw new RangeError(`unknown integrator ${name}`);
    this.integrator = name;
    $('integrator').value = name;
    if (!this.wearable) return;
    for (const a of this.avatars) {
      this.unwear(a);
      this.wear(a);
    }
    this.restartReadout();
  }

  /**
   * After a change of wearable, rig or integrator: the readout forgets the frames before it (their
   * cost was another simulation's) and the substep count starts with the new instances' clocks.
   */
  restartReadout() {
    this.springFrames.clear();
    this.lastSubsteps = null;
    this.lastDt = NaN;
  }

  /** Colliders on or off: the creator rebuilds the rig with or without them. */
  setColliders(on) {
    this.colliders = on;
    $('colliders').checked = on;
    this.onRigOptionsChange?.();
  }

  /**
   * The body colliders slider: every avatar's 'dcl-body' shapes resized (attachment.setColliders
   * with `scale`), 0 to 2, for this instance only: the rig is not rebuilt.
   */
  setBodyScale(value) {
    const scale = Math.min(2, Math.max(0, Number(value)));
    this.bodyScale = Number.isFinite(scale) ? scale : 1;
    $('body-scale').value = String(this.bodyScale);
    $('body-scale-num').textContent = this.bodyScale.toFixed(2);
    for (const a of this.avatars) this.applyBodyScale(a);
  }

  /**
   * The slider's scale on one avatar's attachment. Untouched at 1 (the rig's own shapes); with
   * the colliders off, the rig has none and a scaled avatar gets none either. setRig keeps an
   * attachment's colliders, so after a new rig this says again which it is to have.
   */
  applyBodyScale(avatar) {
    const { attachment } = avatar;
    if (!attachment || (this.bodyScale === 1 && !avatar.bodyScaled)) return;
    avatar.bodyScaled = true;
    if (this.colliders) attachment.setColliders(AVATAR_COLLIDERS, { scale: this.bodyScale });
    else attachment.setColliders(null);
  }

  setShowColliders(show) {
    this.showColliders = show;
    $('show-colliders').checked = show;
    for (const a of this.avatars) a.colliderHelper?.setVisible(show);
  }

  /**
   * How much of each avatar's own motion its hair feels (instance.setInertia), 0 to 1: on every
   * avatar now, and on every instance made later (a new rig, another integrator).
   */
  setInertia(value) {
    this.inertia = Math.min(1, Math.max(0, Number(value)));
    if (!Number.isFinite(this.inertia)) this.inertia = 1;
    $('inertia').value = String(this.inertia);
    $('inertia-num').textContent = this.inertia.toFixed(2);
    for (const a of this.group?.attachments ?? []) a.instance?.setInertia(this.inertia);
  }

  /**
   * Wind of `strength` (world units per second, like gravityPower) on every avatar: from the
   * front and a little from the avatar's right, gusting about every two seconds, the same gusts
   * on every run (a fixed seed).
   */
  setWind(strength) {
    this.wind = Math.min(kMaxDemoWind, Math.max(0, Number(strength) || 0));
    $('wind').value = String(this.wind);
    $('wind-num').textContent = this.wind.toFixed(1);
    this.group?.scene.setWind(this.wind > 0 ? { direction: [-0.3, 0, -1], strength: this.wind, gustFrequency: 0.5, seed: 1 } : null);
  }

  /**
   * Simulate only the `n` avatars nearest to the camera (null: all). Applied by every step, so
   * orbiting or zooming changes which ones move; the core holds the others' pose and restarts
   * them from rest when they come back.
   */
  setBudget(n) {
    this.budget = n === null ? null : Math.max(0, Math.floor(Number(n)) || 0);
    $('budget').value = this.budget === null ? 'all' : String(this.budget);
  }

  /** How many avatars, and how many of their joints, the last scene.step simulated. */
  simulatedCount() {
    if (!this.group) return { avatars: 0, joints: 0, of: 0 };
    const scene = this.group.scene;
    let avatars = 0;
    let joints = 0;
    for (const a of this.avatars) {
      if (a.attachment && scene.isActive(a.attachment.instance)) {
        avatars++;
        joints += a.attachment.jointObjects.length;
      }
    }
    return { avatars, joints, of: this.group.attachments.length };
  }

  // ---- the frame

  frame(timestamp) {
    this.timer.update(timestamp);
    const dt = Math.min(this.timer.getDelta(), kMaxFrameDt);
    this.advance(this.paused ? 0 : dt);
    this.controls.update();
    this.renderer.render(this.scene, this.camera);
    if (this.frameCount === 0) performance.mark('first-drawable-frame');  // the avatar, drawn
    this.frameTimes[this.frameCount++ % this.frameTimes.length] = dt;
    const now = performance.now();
    if (now - this.lastReadout > 250) {
      this.lastReadout = now;
      this.updateReadout();
    }
  }

  /** One frame of dt seconds: animation, avatar transforms, then the springs. */
  advance(dt) {
    if (dt > 0) {
      if (this.spin) this.setYaw(this.yaw + kSpinSpeed * dt);
      if (this.shakeTime >= 0) {
        this.shakeTime += dt;
        if (this.shakeTime > kShakeSeconds) this.shakeTime = -1;
      }
      this.placeAvatars();
      for (const a of this.avatars) a.mixer.update(dt);
    }
    // The drivers' matrixWorld must be current before the springs read them.
    this.scene.updateMatrixWorld();
    if (dt > 0 && this.group) this.simulate(dt);  // no group until the module is ready
  }

  /**
   * Drivers of every avatar in, one scene.step for all of them, rotations out (group.update).
   * The group's readDrivers() skips drivers without an object, so the avatar bones found by name
   * for node -1 drivers are written first and kept.
   */
  simulate(dt) {
    const t0 = performance.now();
    for (const a of this.avatars) this.writeExtraDrivers(a);
    this.drag.apply();
    if (this.budget === null) {
      this.group.scene.setBudget(null);
    } else {
      this.camera.getWorldPosition(kViewerScratch);
      this.group.scene.setBudget(this.budget, kViewerScratch.x, kViewerScratch.y, kViewerScratch.z);
    }
    this.group.update(dt);
    const t1 = performance.now();
    this.springFrames.add(t1, t1 - t0, this.jointCount, this.integrator);
    // The core's count; with a budget some avatars are held (0 steps), so the most any took.
    let steps = 0;
    for (const a of this.avatars) if (a.attachment) steps = Math.max(steps, a.attachment.instance.lastSteps);
    this.lastSubsteps = steps;
    this.lastDt = dt;
  }

  /** The avatar bones found by name for node -1 drivers, into the instance (see simulate). */
  writeExtraDrivers(a) {
    if (!a.attachment || a.extraDrivers.length === 0) return;
    const matrices = a.attachment.instance.driverMatrices;
    for (const { index, elements } of a.extraDrivers) {
      for (let i = 0; i < 16; i++) matrices[index * 16 + i] = elements[i];
    }
  }

  /** The median ms per frame of the springs over the last second (NaN without a frame in it). */
  springMsMedian(now = performance.now()) {
    return this.springFrames.medianMs(now);
  }

  fps() {
    const n = Math.min(this.frameCount, this.frameTimes.length);
    let sum = 0;
    for (let i = 0; i < n; i++) sum += this.frameTimes[i];
    return sum > 0 ? n / sum : NaN;
  }

  /** The readout as of `now` (one instant for the median and its frame count). */
  updateReadout(now = performance.now()) {
    const simulated = this.simulatedCount();
    const joints = simulated.joints;
    const ms = this.springMsMedian(now);
    $('readout-joints').textContent = String(joints);
    $('readout-active').textContent = String(simulated.avatars);
    $('readout-avatars').textContent = String(simulated.of);
    $('readout-integrator').textContent = this.integrator.toUpperCase();
    $('readout-solver').textContent = Number.isFinite(ms) ? ms.toFixed(3) : '–';
    $('readout-per-joint').textContent = Number.isFinite(ms) && joints ? `(${((ms * 1e6) / joints).toFixed(0)} ns/joint)` : '';
    $('readout-frames').textContent = String(this.springFrames.samples(now).length);
    $('readout-substeps').textContent = this.lastSubsteps === null ? '–' : String(this.lastSubsteps);
    $('readout-dt').textContent = Number.isFinite(this.lastDt) ? (this.lastDt * 1000).toFixed(1) : '–';
    const fps = this.fps();
    $('readout-fps').textContent = Number.isFinite(fps) ? fps.toFixed(0) : '–';
  }

  /**
   * Times the springs alone: `frames` back-to-back frames of drivers in, one scene.step, rotations
   * out, at 60 Hz, the avatars frozen. More precise than the readout, whose per-frame samples are
   * near the browser's timer resolution.
   */
  benchmark(frames = 300) {
    this.scene.updateMatrixWorld();
    const t0 = performance.now();
    for (let f = 0; f < frames; f++) this.simulate(1 / 60);
    const ms = (performance.now() - t0) / frames;
    const joints = this.jointCount;
    return { msPerFrame: ms, joints, avatars: this.avatars.length, nsPerJoint: joints ? (ms * 1e6) / joints : NaN };
  }
}

async function fetchBytes(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  return new Uint8Array(await response.arrayBuffer());
}

function disposeGltf(gltf) {
  gltf.scene.traverse((o) => {
    if (o.geometry) o.geometry.dispose();
    if (o.material) for (const m of [o.material].flat()) m.dispose();
  });
}

// ---------------------------------------------------------------------------------------------
// Wiring

function wireControls(preview) {
  $('animation').addEventListener('change', (e) => preview.setAnimation(e.target.value));
  const turn = (e) => preview.setYaw(Number(e.target.value) || 0);
  $('turn').addEventListener('input', turn);
  $('turn-num').addEventListener('change', turn);
  $('spin').addEventListener('change', (e) => { preview.spin = e.target.checked; });
  $('shake').addEventListener('click', () => preview.shake());
  $('pause').addEventListener('click', () => preview.setPaused(!preview.paused));
  $('reset').addEventListener('click', () => preview.reset());
  $('show-chains').addEventListener('change', (e) => preview.setShowChains(e.target.checked));
  $('show-body').addEventListener('change', (e) => preview.setShowBody(e.target.checked));
  $('integrator').addEventListener('change', (e) => preview.setIntegrator(e.target.value));
  $('view-preset').addEventListener('change', (e) => preview.setView(e.target.value));
  $('colliders').addEventListener('change', (e) => preview.setColliders(e.target.checked));
  $('show-colliders').addEventListener('change', (e) => preview.setShowColliders(e.target.checked));
  $('wind').addEventListener('input', (e) => preview.setWind(e.target.value));
  $('inertia').addEventListener('input', (e) => preview.setInertia(e.target.value));
  $('body-scale').addEventListener('input', (e) => preview.setBodyScale(e.target.value));
  $('budget').addEventListener('change', (e) => preview.setBudget(e.target.value === 'all' ? null : Number(e.target.value)));
  $('avatars').addEventListener('change', (e) => {
    preview.setAvatarCount(Number(e.target.value));
    e.target.value = String(preview.avatars.length);
  });
}

/** window.springbonesDemo: read-only state and the same controls as the panel, for tests. */
function debugHook(preview, creator) {
  const first = () => preview.avatars[0]?.attachment;
  return Object.freeze({
    get ready() { return preview.wearable !== null; },
    /** Joint names of the worn item, in rotation order. */
    jointNames: () => (first() ? first().rig.joints.map((j) => j.name) : []),
    /** A copy of an avatar's (default: the first's) joint rotations (x, y, z, w per joint). */
    rotations: (avatar = 0) => {
      const attachment = preview.avatars[avatar]?.attachment;
      return attachment ? Array.from(attachment.instance.rotations) : [];
    },
    /** World position of a node of the first avatar (e.g. a chain tip). */
    worldPosition: (name) => {
      const o = preview.avatars[0]?.root.getObjectByName(name);
      return o ? o.getWorldPosition(new THREE.Vector3()).toArray() : null;
    },
    state: () => ({
      animation: preview.animation,
      shaking: preview.shakeTime >= 0,
      spin: preview.spin,
      paused: preview.paused,
      yaw: preview.yaw,
      avatars: preview.avatars.length,
      joints: preview.jointCount,
      wearable: preview.wearable?.label ?? null,
      contentHash: creator.hash,
      springMsPerFrame: preview.springMsMedian(),
      integrator: preview.integrator,
      colliders: preview.colliders,
      wind: preview.wind,
      bodyScale: preview.bodyScale,
      rigColliders: first()?.rig.colliders.length ?? 0,
      rigWarnings: first()?.rig.warnings.map((w) => w.code) ?? [],
      collidersShown: preview.avatars.reduce((n, a) => n + (a.colliderHelper?.lines.filter((l) => l.visible && l.parent).length ?? 0), 0),
      chainsShown: preview.avatars.filter((a) => a.helper?.visible && a.helper.parent).length,
      sceneSize: preview.group.scene.size,
      instances: preview.avatars.filter((a) => a.attachment && preview.group.scene.slotOf(a.attachment.instance) >= 0).length,
      fps: preview.fps(),
      budget: preview.budget,
      simulated: preview.simulatedCount().avatars,
      jumps: preview.avatars.reduce((n, a) => n + (a.attachment?.instance.jumps ?? 0), 0),
      messages: creator.messageList(),
      validation: creator.validationList(),
    }),
    entries: () => structuredClone(creator.entries),
    setAnimation: (name) => { $('animation').value = name; preview.setAnimation(name); },
    setPaused: (paused) => preview.setPaused(Boolean(paused)),
    setYaw: (degrees) => preview.setYaw(degrees),
    setAvatarCount: (n) => { preview.setAvatarCount(n); $('avatars').value = String(preview.avatars.length); },
    shake: () => preview.shake(),
    setSpin: (on) => { $('spin').checked = Boolean(on); preview.spin = Boolean(on); },
    reset: () => preview.reset(),
    /** The springs back to the rest pose (attachment.reset()): the next frame falls from it. */
    restartSprings: () => { for (const a of preview.avatars) a.attachment?.reset(); },
    /** Where the first avatar draws a joint's tail, in the page's CSS pixels (null: not drawn). */
    tailOnScreen: (name) => {
      const attachment = first();
      const j = attachment ? attachment.rig.joints.findIndex((x) => x.name === name) : -1;
      const tail = j >= 0 ? attachment.tailObjects[j] : null;
      if (!tail) return null;
      const p = tail.getWorldPosition(new THREE.Vector3()).project(preview.camera);
      const rect = preview.renderer.domElement.getBoundingClientRect();
      return { x: rect.left + ((p.x + 1) / 2) * rect.width, y: rect.top + ((1 - p.y) / 2) * rect.height };
    },
    /** The joint the mouse holds on the first avatar (instance.grabbedJoint), -1 for none. */
    grabbedJoint: () => first()?.instance.grabbedJoint ?? -1,
    /** Advances `seconds` in fixed frames of dt (use while paused: deterministic). */
    advance: (seconds, dt = 1 / 60) => {
      for (let t = 0; t < seconds - 1e-9; t += dt) preview.advance(dt);
    },
    benchmark: (frames) => preview.benchmark(frames),
    /**
     * The readout, refreshed now: the median solver ms and the frame samples of the last second it
     * is the median of ({ at, ms, joints, integrator }), how many samples it holds however old,
     * the last frame's substeps and dt, and the text the page shows for them.
     */
    readout: () => {
      const now = performance.now();
      preview.updateReadout(now);
      return {
        now,
        medianMs: preview.springFrames.medianMs(now),
        samples: preview.springFrames.samples(now),
        held: preview.springFrames.held,
        substeps: preview.lastSubsteps,
        dt: preview.lastDt,
        shown: { solver: $('readout-solver').textContent, frames: $('readout-frames').textContent, substeps: $('readout-substeps').textContent },
      };
    },
    setIntegrator: (name) => preview.setIntegrator(name),
    setView: (name) => preview.setView(name),
    /**
     * Where the first avatar is drawn: the screen rectangle (page CSS pixels) of its skinned
     * meshes' bounds in the current pose, and per ponytail joint its normalised device
     * coordinates and whether the head (a sphere 9 cm above the head bone, radius 9.5 cm, as the
     * body colliders') hides it from the camera.
     */
    onScreen: () => {
      const a = preview.avatars[0];
      preview.scene.updateMatrixWorld();
      preview.camera.updateMatrixWorld();
      const box = new THREE.Box3();
      a.root.traverse((o) => {
        if (!o.isSkinnedMesh) return;
        o.computeBoundingBox();  // in the current pose
        box.union(o.boundingBox.clone().applyMatrix4(o.matrixWorld));
      });
      const canvas = preview.renderer.domElement.getBoundingClientRect();
      const corners = [];
      for (let i = 0; i < 8; i++) {
        const p = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y, i & 4 ? box.max.z : box.min.z).project(preview.camera);
        corners.push([canvas.left + (p.x + 1) / 2 * canvas.width, canvas.top + (1 - p.y) / 2 * canvas.height]);
      }
      const xs = corners.map((c) => c[0]);
      const ys = corners.map((c) => c[1]);
      const head = avatarArmature(a.root).get('Avatar_Head');
      const centre = new THREE.Vector3(0, 9, 0).applyMatrix4(head.matrixWorld);
      const radius = 0.095;
      const eye = preview.camera.getWorldPosition(new THREE.Vector3());
      const ponytail = (a.attachment?.jointObjects ?? []).filter((o) => o && /ponytail/i.test(o.name)).map((o) => {
        const p = o.getWorldPosition(new THREE.Vector3());
        // Hidden when the segment from the eye to the joint passes through the head sphere.
        const ray = new THREE.Ray(eye, p.clone().sub(eye).normalize());
        const hit = ray.intersectSphere(new THREE.Sphere(centre, radius), new THREE.Vector3());
        return { name: o.name, ndc: p.clone().project(preview.camera).toArray(), hidden: hit !== null && hit.distanceTo(eye) < p.distanceTo(eye) };
      });
      return {
        avatar: { left: Math.min(...xs), right: Math.max(...xs), top: Math.min(...ys), bottom: Math.max(...ys) },
        canvas: { left: canvas.left, right: canvas.right, top: canvas.top, bottom: canvas.bottom },
        ponytail,
      };
    },
    /** The parameters and center the first avatar's rig gives a joint (null if not simulated). */
    joint: (name) => {
      const rig = first()?.rig;
      const j = rig?.joints.find((x) => x.name === name);
      return j ? { params: structuredClone(j.params), center: j.centerDriver >= 0 ? rig.drivers[j.centerDriver].name : null } : null;
    },
    /**
     * Per avatar: whether the last step simulated it, and its root's distance from the camera
     * (where the camera is now; the budget used where it was at that step).
     */
    activeAvatars: () => {
      const camera = preview.camera.getWorldPosition(new THREE.Vector3());
      return preview.avatars.map((a) => ({
        active: Boolean(a.attachment && preview.group.scene.isActive(a.attachment.instance)),
        distance: a.root.getWorldPosition(new THREE.Vector3()).distanceTo(camera),
      }));
    },
    setBudget: (n) => preview.setBudget(n),
    setWind: (strength) => preview.setWind(strength),
    setInertia: (value) => preview.setInertia(value),
    setBodyScale: (value) => preview.setBodyScale(value),
    setColliders: (on) => preview.setColliders(Boolean(on)),
    setShowColliders: (show) => preview.setShowColliders(Boolean(show)),
    /**
     * How far the first avatar's joint tails are outside its head sphere (the body colliders'
     * head sphere of the last rig that had them, whether or not the rig has colliders now), from
     * the instance's world matrices after the last step: { clearance (metres, negative inside),
     * joint, radius }.
     */
    headClearance: () => {
      const a = preview.avatars[0];
      const sphere = preview.headSphere;
      const head = a && sphere && avatarArmature(a.root).get(sphere.node);
      if (!a?.attachment || !head) return null;
      const { rig, instance } = a.attachment;
      const centre = new THREE.Vector3().fromArray(sphere.offset).applyMatrix4(head.matrixWorld);
      const radius = sphere.radius * head.matrixWorld.getMaxScaleOnAxis();
      const world = instance.worldMatrices;
      const m = new THREE.Matrix4();
      const tail = new THREE.Vector3();
      let best = { clearance: Infinity, joint: null, radius };
      rig.joints.forEach((j, i) => {
        m.fromArray(world, i * 16);
        tail.fromArray(j.tailOffset).applyMatrix4(m);
        const clearance = tail.distanceTo(centre) - radius;
        if (clearance < best.clearance) best = { clearance, joint: j.name, radius };
      });
      return best;
    },
    exportText: () => creator.exportText(),
  });
}

async function main() {
  const preview = new Preview();
  wireControls(preview);
  try {
    await preview.init();
    const creator = new Creator(preview);
    preview.onRigOptionsChange = () => creator.rebuild();
    await creator.loadSample();
    window.springbonesDemo = debugHook(preview, creator);
    $('boot').textContent = '';
  } catch (e) {
    $('boot').textContent = `Could not start the preview: ${e.message}`;
    $('boot').classList.add('failed');
    throw e;
  }
}

main();
