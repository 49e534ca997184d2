export * from './springBoneSimulation.js';
