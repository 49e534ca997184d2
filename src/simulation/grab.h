// Holding a joint toward a point (Instance::grab, docs/semantics.md "Grab"), shared by the general
// VRM path and the XPBD integrator (a grabbing instance leaves the lane path while it holds).
//
// A grab is one pass of FABRIK-style reaching per step: before the step, a backward pass from the
// point up the chain (the joints from the chain root to the grabbed one, as the last step left
// them) gives each of those joints the point its anchor should aim at (its child on the path's
// head, or for the grabbed joint its own tail); in the step, parents first, each of them turns its
// rest pose under the parent it now has so that its anchor aims at that point, which is the
// forward pass. The turned tail then goes through the length constraint and the colliders as any
// tail does, so they still hold. Over the steps of a few frames the passes converge, and a point
// beyond the chain's reach leaves the chain stretched toward it. Defined in grab.cpp, out of the
// -O3 per-frame files (wasm/CMakeLists.txt): a grab is one instance's, rarely.
#pragma once

#include <cstddef>
#include <vector>

#include "common/glm_interop.h"
#include "springbones/springbones.h"

namespace springbones {

/// The joints a grab holds and where each aims this step.
struct HeldJoints {
  std::vector<int> slot;          ///< per rig joint: its index in the path, or -1
  std::vector<int> path;          ///< rig joints from the chain root down to the grabbed one
  std::vector<glm::vec3> anchor;  ///< per path joint, in its local space: the next path joint's
                                  ///< rest translation, or the grabbed joint's tail
  std::vector<glm::vec3> reach;   ///< per path joint, world: where its anchor aims this step
  bool active = false;

  /// Holds `joint` of `rig` (in range): the path from its chain root down to it, with anchors.
  /// Allocates nothing once slot and the vectors are sized to the rig's joints.
  void hold(const Rig& rig, std::size_t joint);
  /// Holds nothing.
  void letGo();

  /// Where a held joint's tail goes under a head and rest transform (rest_linear, the joint at its
  /// rest rotation under its current parent; rest_offset, its rest tail offset in world): the rest
  /// offset turned by the rotation taking the anchor at rest onto the direction of the reach
  /// point. A degenerate anchor or a reach point on the head leaves the tail at `fallback`.
  glm::vec3 tail(std::size_t k, const glm::vec3& head, const glm::mat3& rest_linear, const glm::vec3& rest_offset,
                 const glm::vec3& fallback) const;

  /// The backward pass toward `point` (world), from the path joints' world transforms after the
  /// last step: the grabbed joint's anchor aims at the point, and each joint above at where the
  /// joint below would have its head, its anchor's length back from that joint's aim point along
  /// the line to its present head.
  void prepare(const glm::vec3& point, const glm::mat4* joint_world);
};

}  // namespace springbones
