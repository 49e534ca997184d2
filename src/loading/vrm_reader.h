// The VRM spring-bone reader (vrm_loader.cpp) on a typed value.
#pragma once

#include <memory>

#include "common/typed_value.h"
#include "springbones/springbones.h"
#include "springbones/vrm.h"

namespace springbones {

/// The hierarchy and the spring bones of a document given as {asset, nodes, extensions}.
Error loadVrm(const TypedValue& gltf, std::shared_ptr<const Rig>& out, VrmSpringFormat* format);

}  // namespace springbones
