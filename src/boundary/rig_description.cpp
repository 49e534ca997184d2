// describeRig: the rig as one JSON text, built as a nlohmann value with float numbers.
#include "boundary/rig_description.h"

#include <utility>

#include "springbones/boundary.h"

namespace springbones {
namespace {

FloatJson vec3(const Vec3& v) { return FloatJson::array({v.x, v.y, v.z}); }

// The joint's angle limit as loadRig's `limits` option and VRMC_springBone_limit spell it, or null.
FloatJson limitJson(const JointLimit& limit) {
  FloatJson shape;
  const char* kind = nullptr;
  switch (limit.kind) {
    case JointLimit::Kind::kNone:
      return nullptr;
    case JointLimit::Kind::kCone:
    case JointLimit::Kind::kHinge:
      kind = limit.kind == JointLimit::Kind::kCone ? "cone" : "hinge";
      shape["angle"] = limit.angle;
      break;
    case JointLimit::Kind::kSpherical:
      kind = "spherical";
      shape["pitch"] = limit.pitch;
      shape["yaw"] = limit.yaw;
      break;
  }
  shape["rotation"] = FloatJson::array({limit.rotation.x, limit.rotation.y, limit.rotation.z, limit.rotation.w});
  FloatJson out;
  out[kind] = std::move(shape);
  return out;
}

FloatJson jointJson(const Rig& rig, const Joint& j) {
  const auto& nodes = rig.skeleton.nodes;
  const auto nodeName = [&](int node) -> FloatJson {
    if (node < 0 || static_cast<std::size_t>(node) >= nodes.size()) return nullptr;
    return nodes[node].name;
  };
  // tail_node is -1 for a VRM 0.x leaf's virtual tail: no node, tail_local is the truth.
  const bool tail_is_node = j.tail_node >= 0 && static_cast<std::size_t>(j.tail_node) < nodes.size();
  return FloatJson{{"name", nodeName(j.node)},
                   {"node", j.node},
                   {"tail", tail_is_node ? nodeName(j.tail_node) : FloatJson(nullptr)},
                   {"tailNode", tail_is_node ? j.tail_node : -1},
                   {"parent", j.parent_joint},
                   {"parentDriver", j.parent_driver},
                   {"centerDriver", j.center_driver},
                   {"chain", j.chain},
                   {"params",
                    {{"stiffness", j.params.stiffness},
                     {"gravityPower", j.params.gravity_power},
                     {"gravityDir", vec3(j.params.gravity_dir)},
                     {"drag", j.params.drag}}},
                   {"tailOffset", vec3(j.tail_local)},
                   {"restLength", j.rest_length},
                   {"hitRadius", j.hit_radius},
                   {"limit", limitJson(j.limit)}};
}

FloatJson colliderJson(const Rig& rig, const Collider& c) {
  const bool has_driver = c.driver >= 0 && static_cast<std::size_t>(c.driver) < rig.drivers.size();
  FloatJson out{{"driver", c.driver},
                {"node", has_driver ? FloatJson(rig.drivers[c.driver].name) : FloatJson(nullptr)},
                {"offset", vec3(c.offset)},
                {"radius", c.radius}};
  if (c.shape == Collider::Shape::kCapsule) {
    out["shape"] = "capsule";
    out["tail"] = vec3(c.tail);
  } else if (c.shape == Collider::Shape::kPlane) {
    out["shape"] = "plane";
    out["normal"] = vec3(c.normal);
  } else {
    out["shape"] = "sphere";
  }
  out["inside"] = c.inside;
  return out;
}

}  // namespace

std::string describeRig(const Rig& rig, const std::string& content_hash, const std::string& format) {
  FloatJson joints = FloatJson::array();
  for (const Joint& j : rig.joints) joints.push_back(jointJson(rig, j));
  FloatJson drivers = FloatJson::array();
  for (const Driver& d : rig.drivers) drivers.push_back(FloatJson{{"name", d.name}, {"node", d.node}});
  FloatJson colliders = FloatJson::array();
  for (const Collider& c : rig.colliders) colliders.push_back(colliderJson(rig, c));
  FloatJson warnings = FloatJson::array();
  for (const Warning& w : rig.warnings) {
    warnings.push_back(FloatJson{{"code", w.code}, {"message", w.message}, {"path", w.path}});
  }
  const FloatJson description{{"contentHash", content_hash},
                              {"format", format},
                              {"nodeCount", rig.skeleton.nodes.size()},
                              {"joints", std::move(joints)},
                              {"chains", rig.chain_roots},
                              {"drivers", std::move(drivers)},
                              {"colliders", std::move(colliders)},
                              {"warnings", std::move(warnings)}};
  return dumpReplacingInvalidUtf8(description);
}

}  // namespace springbones
