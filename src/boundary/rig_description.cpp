// describeRig and describeColliderChange (springbones/boundary.h), written with TypedWriter.
#include <cmath>

#include "boundary/page_text.h"
#include "common/typed_value.h"
#include "springbones/boundary.h"

namespace springbones {
namespace {

// A float as JSON showed it: non-finite ones as null.
void floatValue(TypedWriter& out, float v) {
  if (std::isfinite(v)) {
    out.float32(v);
  } else {
    out.null();
  }
}

void nodeName(TypedWriter& out, const Rig& rig, int node) {
  const auto& nodes = rig.skeleton.nodes;
  if (node < 0 || static_cast<std::size_t>(node) >= nodes.size()) {
    out.null();
  } else {
    pageText(out, nodes[node].name);
  }
}

void vec3(TypedWriter& out, const Vec3& v) {
  out.array(3);
  floatValue(out, v.x);
  floatValue(out, v.y);
  floatValue(out, v.z);
}

// The joint's angle limit as loadRig's `limits` option and VRMC_springBone_limit spell it, or null.
void limit(TypedWriter& out, const JointLimit& l) {
  if (l.kind == JointLimit::Kind::kNone) {
    out.null();
    return;
  }
  const bool spherical = l.kind == JointLimit::Kind::kSpherical;
  out.object(1);
  out.key(l.kind == JointLimit::Kind::kCone ? "cone" : l.kind == JointLimit::Kind::kHinge ? "hinge" : "spherical");
  out.object(spherical ? 3 : 2);
  out.key(spherical ? "pitch" : "angle");
  floatValue(out, spherical ? l.pitch : l.angle);
  out.key("rotation");
  out.array(4);
  for (float c : {l.rotation.x, l.rotation.y, l.rotation.z, l.rotation.w}) floatValue(out, c);
  if (spherical) {
    out.key("yaw");
    floatValue(out, l.yaw);
  }
}

// Members in key order, as the description has always been written.
void joint(TypedWriter& out, const Rig& rig, const Joint& j) {
  // tail_node is -1 for a VRM 0.x leaf's virtual tail: no node, tail_local is the truth.
  const bool tail_is_node = j.tail_node >= 0 && static_cast<std::size_t>(j.tail_node) < rig.skeleton.nodes.size();
  out.object(13);
  out.key("centerDriver");
  out.number(j.center_driver);
  out.key("chain");
  out.number(j.chain);
  out.key("hitRadius");
  floatValue(out, j.hit_radius);
  out.key("limit");
  limit(out, j.limit);
  out.key("name");
  nodeName(out, rig, j.node);
  out.key("node");
  out.number(j.node);
  out.key("params");
  out.object(4);
  out.key("drag");
  floatValue(out, j.params.drag);
  out.key("gravityDir");
  vec3(out, j.params.gravity_dir);
  out.key("gravityPower");
  floatValue(out, j.params.gravity_power);
  out.key("stiffness");
  floatValue(out, j.params.stiffness);
  out.key("parent");
  out.number(j.parent_joint);
  out.key("parentDriver");
  out.number(j.parent_driver);
  out.key("restLength");
  floatValue(out, j.rest_length);
  out.key("tail");
  nodeName(out, rig, tail_is_node ? j.tail_node : -1);
  out.key("tailNode");
  out.number(tail_is_node ? j.tail_node : -1);
  out.key("tailOffset");
  vec3(out, j.tail_local);
}

void collider(TypedWriter& out, const Rig& rig, const Collider& c) {
  const bool has_driver = c.driver >= 0 && static_cast<std::size_t>(c.driver) < rig.drivers.size();
  const bool plane = c.shape == Collider::Shape::kPlane;
  const bool capsule = c.shape == Collider::Shape::kCapsule;
  out.object(6 + (plane ? 1 : 0) + (capsule ? 1 : 0));
  out.key("driver");
  out.number(c.driver);
  out.key("inside");
  out.boolean(c.inside);
  out.key("node");
  if (has_driver) {
    pageText(out, rig.drivers[c.driver].name);
  } else {
    out.null();
  }
  if (plane) {
    out.key("normal");
    vec3(out, c.normal);
  }
  out.key("offset");
  vec3(out, c.offset);
  out.key("radius");
  floatValue(out, c.radius);
  out.key("shape");
  pageText(out, capsule ? "capsule" : plane ? "plane" : "sphere");
  if (capsule) {
    out.key("tail");
    vec3(out, c.tail);
  }
}

void writeWarnings(TypedWriter& out, const std::vector<Warning>& warnings) {
  out.array(static_cast<std::uint32_t>(warnings.size()));
  for (const Warning& w : warnings) pageCodeMessagePath(out, w.code, w.message, w.path);
}

}  // namespace

std::vector<std::uint8_t> describeRig(const Rig& rig, const std::string& content_hash, const std::string& format) {
  TypedWriter out;
  out.object(8);
  out.key("chains");
  out.array(static_cast<std::uint32_t>(rig.chain_roots.size()));
  for (int root : rig.chain_roots) out.number(root);
  out.key("colliders");
  out.array(static_cast<std::uint32_t>(rig.colliders.size()));
  for (const Collider& c : rig.colliders) collider(out, rig, c);
  out.key("contentHash");
  pageText(out, content_hash);
  out.key("drivers");
  out.array(static_cast<std::uint32_t>(rig.drivers.size()));
  for (const Driver& d : rig.drivers) {
    out.object(2);
    out.key("name");
    pageText(out, d.name);
    out.key("node");
    out.number(d.node);
  }
  out.key("format");
  pageText(out, format);
  out.key("joints");
  out.array(static_cast<std::uint32_t>(rig.joints.size()));
  for (const Joint& j : rig.joints) joint(out, rig, j);
  out.key("nodeCount");
  out.number(static_cast<double>(rig.skeleton.nodes.size()));
  out.key("warnings");
  writeWarnings(out, rig.warnings);
  return std::move(out.bytes());
}

std::vector<std::uint8_t> describeColliderChange(const std::vector<std::string>& frames,
                                                 const std::vector<Warning>& warnings) {
  TypedWriter out;
  out.object(2);
  out.key("frames");
  out.array(static_cast<std::uint32_t>(frames.size()));
  for (const std::string& name : frames) pageText(out, name);
  out.key("warnings");
  writeWarnings(out, warnings);
  return std::move(out.bytes());
}

}  // namespace springbones
