// loadVrm's answer as plain data, one scenario for Node and Chromium (tests/browser/load_vrm.test.mjs
// compares the two): a rig's description and the rotations of an instance of it after frames of its
// first driver moving.

/** What a page's loader hands over for a GLB: its JSON chunk, parsed. */
export function glbJson(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const length = view.getUint32(12, true);
  return JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + length)));
}

/** The rig's format, joints and warnings and the rotations after 30 frames; disposes of the rig. */
export function vrmSummary(rig) {
  const inst = rig.createInstance();
  for (let frame = 0; frame < 30; frame++) {
    inst.driverMatrices[12] += 0.01;
    inst.step(1 / 60);
  }
  const result = { format: rig.format, joints: rig.joints, warnings: rig.warnings, rotations: Array.from(inst.rotations) };
  inst.dispose();
  rig.dispose();
  return result;
}
