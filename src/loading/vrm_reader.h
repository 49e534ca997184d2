// The VRM spring-bone reader on a typed value (vrm_loader.cpp, over vrm_formats.h and
// vrm_rig_builder.h).
#pragma once

#include <memory>

#include "common/typed_value.h"
#include "springbones/springbones.h"
#include "springbones/vrm.h"

namespace springbones {

/// The hierarchy and the spring bones of a document given as {asset, nodes, extensions}.
Error loadVrm(const TypedValue& gltf, std::shared_ptr<const Rig>& out, VrmSpringFormat* format);

}  // namespace springbones
