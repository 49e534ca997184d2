// describeRig: the rig as one JSON text (springbones/boundary.h), written with JsonText.
#include "springbones/boundary.h"

#include "common/json_text.h"

namespace springbones {
namespace {

void nodeName(JsonText& out, const Rig& rig, int node) {
  const auto& nodes = rig.skeleton.nodes;
  if (node < 0 || static_cast<std::size_t>(node) >= nodes.size()) {
    out.null();
  } else {
    out.value(nodes[node].name);
  }
}

void vec3(JsonText& out, const Vec3& v) { out.vec3(v.x, v.y, v.z); }

// The joint's angle limit as loadRig's `limits` option and VRMC_springBone_limit spell it, or null.
void limit(JsonText& out, const JointLimit& l) {
  if (l.kind == JointLimit::Kind::kNone) {
    out.null();
    return;
  }
  out.beginObject();
  out.key(l.kind == JointLimit::Kind::kCone ? "cone" : l.kind == JointLimit::Kind::kHinge ? "hinge" : "spherical");
  out.beginObject();
  if (l.kind == JointLimit::Kind::kSpherical) {
    out.key("pitch").value(l.pitch);
  } else {
    out.key("angle").value(l.angle);
  }
  out.key("rotation").beginArray().value(l.rotation.x).value(l.rotation.y).value(l.rotation.z).value(l.rotation.w);
  out.endArray();
  if (l.kind == JointLimit::Kind::kSpherical) out.key("yaw").value(l.yaw);
  out.endObject();
  out.endObject();
}

// Members in key order, as the description has always been written (some callers compare texts).
void joint(JsonText& out, const Rig& rig, const Joint& j) {
  // tail_node is -1 for a VRM 0.x leaf's virtual tail: no node, tail_local is the truth.
  const bool tail_is_node = j.tail_node >= 0 && static_cast<std::size_t>(j.tail_node) < rig.skeleton.nodes.size();
  out.beginObject();
  out.key("centerDriver").value(j.center_driver);
  out.key("chain").value(j.chain);
  out.key("hitRadius").value(j.hit_radius);
  out.key("limit");
  limit(out, j.limit);
  out.key("name");
  nodeName(out, rig, j.node);
  out.key("node").value(j.node);
  out.key("params").beginObject();
  out.key("drag").value(j.params.drag);
  out.key("gravityDir");
  vec3(out, j.params.gravity_dir);
  out.key("gravityPower").value(j.params.gravity_power);
  out.key("stiffness").value(j.params.stiffness);
  out.endObject();
  out.key("parent").value(j.parent_joint);
  out.key("parentDriver").value(j.parent_driver);
  out.key("restLength").value(j.rest_length);
  out.key("tail");
  nodeName(out, rig, tail_is_node ? j.tail_node : -1);
  out.key("tailNode").value(tail_is_node ? j.tail_node : -1);
  out.key("tailOffset");
  vec3(out, j.tail_local);
  out.endObject();
}

void collider(JsonText& out, const Rig& rig, const Collider& c) {
  const bool has_driver = c.driver >= 0 && static_cast<std::size_t>(c.driver) < rig.drivers.size();
  out.beginObject();
  out.key("driver").value(c.driver);
  out.key("inside").value(c.inside);
  out.key("node");
  if (has_driver) {
    out.value(rig.drivers[c.driver].name);
  } else {
    out.null();
  }
  if (c.shape == Collider::Shape::kPlane) {
    out.key("normal");
    vec3(out, c.normal);
  }
  out.key("offset");
  vec3(out, c.offset);
  out.key("radius").value(c.radius);
  out.key("shape").value(c.shape == Collider::Shape::kCapsule ? "capsule"
                         : c.shape == Collider::Shape::kPlane ? "plane"
                                                              : "sphere");
  if (c.shape == Collider::Shape::kCapsule) {
    out.key("tail");
    vec3(out, c.tail);
  }
  out.endObject();
}

void writeWarnings(JsonText& out, const std::vector<Warning>& warnings) {
  out.beginArray();
  for (const Warning& w : warnings) {
    out.beginObject().key("code").value(w.code).key("message").value(w.message).key("path").value(w.path).endObject();
  }
  out.endArray();
}

}  // namespace

std::string describeRig(const Rig& rig, const std::string& content_hash, const std::string& format) {
  JsonText out;
  out.beginObject();
  out.key("chains").beginArray();
  for (int root : rig.chain_roots) out.value(root);
  out.endArray();
  out.key("colliders").beginArray();
  for (const Collider& c : rig.colliders) collider(out, rig, c);
  out.endArray();
  out.key("contentHash").value(content_hash);
  out.key("drivers").beginArray();
  for (const Driver& d : rig.drivers) out.beginObject().key("name").value(d.name).key("node").value(d.node).endObject();
  out.endArray();
  out.key("format").value(format);
  out.key("joints").beginArray();
  for (const Joint& j : rig.joints) joint(out, rig, j);
  out.endArray();
  out.key("nodeCount").value(rig.skeleton.nodes.size());
  out.key("warnings");
  writeWarnings(out, rig.warnings);
  out.endObject();
  return out.take();
}

std::string describeColliderChange(const std::vector<std::string>& frames, const std::vector<Warning>& warnings) {
  JsonText out;
  out.beginObject().key("frames").beginArray();
  for (const std::string& name : frames) out.value(name);
  out.endArray().key("warnings");
  writeWarnings(out, warnings);
  out.endObject();
  return out.take();
}

}  // namespace springbones
