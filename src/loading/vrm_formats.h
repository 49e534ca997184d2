// The two VRM spring-bone formats (springbones/vrm.h), each read into the shared VRM rig
// (vrm_rig_builder.h): vrmc_spring_bone.cpp and vrm0_secondary_animation.cpp. vrm_loader.cpp
// chooses which one a file is read with.
#pragma once

#include "common/typed_value.h"
#include "loading/vrm_rig_builder.h"

namespace springbones {

/// extensions.VRMC_springBone (VRM 1.0): its colliders, collider groups and springs. An Error
/// (kMetadataInvalid, with its path) for a shape that cannot be read at all; everything else
/// skipped or replaced is a warning.
Error readVrmcSpringBone(const TypedValue& extension, VrmRigBuilder& rig);

/// extensions.VRM.secondaryAnimation (VRM 0.x): its collider groups and bone groups, with the same
/// kinds of errors and warnings.
Error readVrm0SecondaryAnimation(const TypedValue& secondary_animation, VrmRigBuilder& rig);

}  // namespace springbones
