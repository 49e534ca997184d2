// Dragging the hair with the mouse on the Babylon page (SpringBoneSimulation.grab / release). A
// press whose ray passes close to a chain's tail takes that joint; while the button is held, the
// pointer's ray meets a plane through the tail facing the camera, and that point is the grab's;
// letting go releases it and the hair swings back. The press is taken in the capture phase, so
// the camera never sees it; a press elsewhere turns the camera as before.

const kPickAngle = 0.04;  // radians between the pointer's ray and a tail that still takes it

export class HairDrag {
  /**
   * @param BABYLON the Babylon namespace
   * @param scene, camera the page's
   * @param simulation a SpringBoneSimulation; itemId the wearable to drag
   * @param tails () => per rig joint its tail node (or null)
   */
  constructor(BABYLON, scene, camera, simulation, itemId, tails) {
    Object.assign(this, { BABYLON, scene, camera, simulation, itemId, tails });
    this.held = null;  // { joint, plane }
    const canvas = scene.getEngine().getRenderingCanvas();
    this.canvas = canvas;
    canvas.parentElement.addEventListener('pointerdown', (e) => this.press(e), { capture: true });
    canvas.addEventListener('pointermove', (e) => this.move(e));
    canvas.addEventListener('pointerup', (e) => this.letGo(e));
    canvas.addEventListener('pointercancel', (e) => this.letGo(e));
  }

  get dragging() {
    return this.held !== null;
  }

  ray(event) {
    const rect = this.canvas.getBoundingClientRect();
    const x = event.clientX - rect.left;
    const y = event.clientY - rect.top;
    return this.scene.createPickingRay(x, y, this.BABYLON.Matrix.Identity(), this.camera);
  }

  press(event) {
    if (event.button !== 0 || event.target !== this.canvas) return;
    const ray = this.ray(event);
    let best = null;
    let bestAngle = kPickAngle;
    this.tails().forEach((tail, joint) => {
      if (!tail) return;
      const to = tail.getAbsolutePosition().subtract(ray.origin);
      const length = to.length();
      if (!(length > 0)) return;
      const angle = Math.acos(Math.min(1, this.BABYLON.Vector3.Dot(to, ray.direction) / length));
      if (angle < bestAngle) {
        bestAngle = angle;
        best = { joint, at: tail.getAbsolutePosition().clone() };
      }
    });
    if (!best) return;
    event.stopPropagation();  // not a camera turn
    event.preventDefault();
    this.canvas.setPointerCapture(event.pointerId);
    const normal = this.camera.getForwardRay().direction;
    this.held = { joint: best.joint, plane: this.BABYLON.Plane.FromPositionAndNormal(best.at, normal) };
    this.simulation.grab(this.itemId, best.joint, best.at);
  }

  move(event) {
    if (!this.held) return;
    const ray = this.ray(event);
    const distance = ray.intersectsPlane(this.held.plane);
    if (distance === null) return;  // parallel: keep the last point
    // The instance holds the last point between moves: no call per frame is needed.
    this.simulation.grab(this.itemId, this.held.joint, ray.origin.add(ray.direction.scale(distance)));
  }

  letGo(event) {
    if (!this.held) return;
    if (this.canvas.hasPointerCapture(event.pointerId)) this.canvas.releasePointerCapture(event.pointerId);
    this.held = null;
    this.simulation.release(this.itemId);
  }
}
