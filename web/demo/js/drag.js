// Dragging the hair with the mouse (instance.grab / release). A press within a few pixels of a
// chain's tail on screen takes that joint; while the button is held, the pointer's ray meets a
// plane through the tail facing the camera, and that point is handed to instance.grab every frame
// (the chain reaches toward it, colliders holding); letting go releases it and the hair swings
// back. The press is taken in the capture phase so the orbit controls never see it; a press
// elsewhere orbits as before.
import * as THREE from 'three';

const kPickPixels = 28;  // how far from a tail, on screen, a press still takes it

export class HairDrag {
  /**
   * @param canvas the renderer's canvas
   * @param camera the camera the scene is drawn with
   * @param attachments () => the attachments that can be grabbed (SpringBonesAttachment[])
   */
  constructor(canvas, camera, attachments) {
    this.canvas = canvas;
    this.camera = camera;
    this.attachments = attachments;
    this.held = null;  // { attachment, joint }
    this.point = new THREE.Vector3();
    this.plane = new THREE.Plane();
    this.raycaster = new THREE.Raycaster();
    this.ndc = new THREE.Vector2();
    this.scratch = new THREE.Vector3();
    this.normal = new THREE.Vector3();
    canvas.parentElement.addEventListener('pointerdown', (e) => this.press(e), { capture: true });
    canvas.addEventListener('pointermove', (e) => this.move(e));
    canvas.addEventListener('pointerup', (e) => this.letGo(e));
    canvas.addEventListener('pointercancel', (e) => this.letGo(e));
  }

  get dragging() {
    return this.held !== null;
  }

  press(event) {
    if (event.button !== 0 || event.target !== this.canvas) return;
    const picked = this.pick(event);
    if (!picked) return;
    event.stopPropagation();  // not an orbit
    event.preventDefault();
    this.canvas.setPointerCapture(event.pointerId);
    this.held = picked;
    this.camera.getWorldDirection(this.normal);
    this.plane.setFromNormalAndCoplanarPoint(this.normal, picked.tail);
    this.point.copy(picked.tail);
  }

  move(event) {
    if (!this.held) return;
    this.setRay(event);
    this.raycaster.ray.intersectPlane(this.plane, this.point);  // no hit (parallel): keep the last point
  }

  letGo(event) {
    if (!this.held) return;
    if (this.canvas.hasPointerCapture(event.pointerId)) this.canvas.releasePointerCapture(event.pointerId);
    this.release();
  }

  release() {
    const { attachment } = this.held ?? {};
    this.held = null;
    if (attachment?.instance && !attachment.instance.disposed) attachment.instance.release();
  }

  /** Before each step: the held joint toward the pointer's point (an attachment gone ends the drag). */
  apply() {
    if (!this.held) return;
    const instance = this.held.attachment.instance;
    if (!instance || instance.disposed || !this.attachments().includes(this.held.attachment)) {
      this.held = null;
      return;
    }
    instance.grab(this.held.joint, [this.point.x, this.point.y, this.point.z]);
  }

  /** The joint whose tail is nearest the pointer on screen, within kPickPixels. */
  pick(event) {
    const rect = this.canvas.getBoundingClientRect();
    let best = null;
    let bestPixels = kPickPixels;
    for (const attachment of this.attachments()) {
      if (!attachment?.instance) continue;
      attachment.tailObjects.forEach((tail, joint) => {
        if (!tail) return;
        const world = tail.getWorldPosition(this.scratch);
        const p = world.clone().project(this.camera);
        if (p.z < -1 || p.z > 1) return;  // behind the camera or beyond its far plane
        const x = rect.left + ((p.x + 1) / 2) * rect.width;
        const y = rect.top + ((1 - p.y) / 2) * rect.height;
        const pixels = Math.hypot(x - event.clientX, y - event.clientY);
        if (pixels < bestPixels) {
          bestPixels = pixels;
          best = { attachment, joint, tail: world.clone() };
        }
      });
    }
    return best;
  }

  setRay(event) {
    const rect = this.canvas.getBoundingClientRect();
    this.ndc.set(((event.clientX - rect.left) / rect.width) * 2 - 1, -((event.clientY - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(this.ndc, this.camera);
  }
}
