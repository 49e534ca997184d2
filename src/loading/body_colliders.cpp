// The 'dcl-body' preset (body_colliders.h). Every Decentraland avatar shares one 62-bone armature,
// so the body's shapes follow from it: each shape is measured in the rest pose's world space from
// the distance between two bones (a "segment": neck to head, spine to spine, shoulder to arm...),
// then written in the carrying bone's own space. The fractions below were fitted to the sample
// mannequin (scripts/generate/make_sample_avatar.mjs), whose body is modelled on Decentraland's proportions;
// docs/semantics.md gives every number with its reason.
#include "loading/body_colliders.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/transform_math.h"

namespace springbones {
namespace {

constexpr float kMinSegment = 1e-6f;

// The bones the preset reads, by their armature names.
enum Bone {
  kSpine1,
  kSpine2,
  kNeck,
  kHead,
  kLeftShoulder,
  kLeftArm,
  kLeftForeArm,
  kRightShoulder,
  kRightArm,
  kRightForeArm,
  kBoneCount
};
constexpr const char* kBoneNames[kBoneCount] = {
    "Avatar_Spine1",  "Avatar_Spine2",      "Avatar_Neck",          "Avatar_Head",     "Avatar_LeftShoulder",
    "Avatar_LeftArm", "Avatar_LeftForeArm", "Avatar_RightShoulder", "Avatar_RightArm", "Avatar_RightForeArm"};

// One shape, carried by `carrier` and measured on the segment from bone `from` to bone `to` in
// the rest pose (length L, unit direction u), all sizes in L:
//  - kSphere: a sphere centred at from + along u;
//  - kAlong: a capsule from `from` to `to`;
//  - kAcross: a capsule across the body, centred at from + along u, its ends half_width to
//    either side along the avatar's left-right axis (world X at rest: every Decentraland avatar
//    faces +Z), made square to u.
enum class Kind { kSphere, kAlong, kAcross };
struct Rule {
  const char* name;
  Kind kind;
  Bone carrier, from, to;
  float along;       // kSphere, kAcross
  float half_width;  // kAcross
  float radius;
};

constexpr Rule kRules[] = {
    // Skull: the sample's is an ellipsoid 9 cm above the head bone, radii 9.2 x 11.2 x 10.2 cm,
    // on a 10 cm neck: a sphere 0.9 L past the head, radius 0.94 L, sits inside it and inside the
    // hair cap, clear of the hair's roots.
    {"head", Kind::kSphere, kHead, kNeck, kHead, 1.9f, 0.0f, 0.94f},
    // Neck: the sample's neck is a capsule of radius 4.8 cm from the neck bone to the head.
    {"neck", Kind::kAlong, kNeck, kNeck, kHead, 0.0f, 0.0f, 0.45f},
    // Upper chest on Spine2, measured on Spine2 -> Neck (16 cm): the sample's chest is an
    // ellipsoid 5 cm up with radii 17 x 11.5 x 11 cm; a capsule 5 cm up, 12 cm wide, radius 11 cm.
    {"chest", Kind::kAcross, kSpine2, kSpine2, kNeck, 0.31f, 0.375f, 0.69f},
    // Lower chest on Spine1, measured on Spine1 -> Spine2 (12 cm): ellipsoid 6 cm up, radii
    // 15 x 9 x 10 cm; a capsule 6 cm up, 10 cm wide, radius 9.5 cm.
    {"upper-belly", Kind::kAcross, kSpine1, kSpine1, kSpine2, 0.5f, 0.42f, 0.79f},
    // Shoulders: Shoulder -> Arm (12 cm), the sample's capsule has radius 4.5 to 5 cm.
    {"left-shoulder", Kind::kAlong, kLeftShoulder, kLeftShoulder, kLeftArm, 0.0f, 0.0f, 0.4f},
    {"right-shoulder", Kind::kAlong, kRightShoulder, kRightShoulder, kRightArm, 0.0f, 0.0f, 0.4f},
    // Upper arms: Arm -> ForeArm (27 cm), radius 4.6 cm.
    {"left-upper-arm", Kind::kAlong, kLeftArm, kLeftArm, kLeftForeArm, 0.0f, 0.0f, 0.17f},
    {"right-upper-arm", Kind::kAlong, kRightArm, kRightArm, kRightForeArm, 0.0f, 0.0f, 0.17f},
};

float largestAxisScale(const glm::mat4& m) {
  return std::max({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2]))});
}

}  // namespace

const std::vector<std::string>& dclBodyShapeNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const Rule& rule : kRules) out.emplace_back(rule.name);
    return out;
  }();
  return names;
}

std::vector<ColliderSpec> dclBodyColliders(const Skeleton& skeleton, const std::vector<AvatarBone>& avatar,
                                           std::vector<Warning>& warnings, const BodyColliderOptions& body) {
  // The rest world matrix of each bone: the first of its name, in one pass over the avatar's bones
  // when the caller gave them (all from one space: never mixed with the GLB's), else the GLB's nodes.
  const Mat4* rest[kBoneCount] = {};
  const auto find = [&](const std::string& name, const Mat4& matrix) {
    for (int b = 0; b < kBoneCount; ++b) {
      if (rest[b] == nullptr && name == kBoneNames[b]) rest[b] = &matrix;
    }
  };
  const bool from_avatar = !avatar.empty();
  if (from_avatar) {
    for (const AvatarBone& bone : avatar) find(bone.name, bone.rest_world);
  } else {
    for (const SkeletonNode& n : skeleton.nodes) find(n.name, n.rest_world);
  }
  const auto position = [&](Bone b) { return glm::vec3(toGlm(*rest[b])[3]); };

  std::vector<ColliderSpec> out;
  std::string skipped;
  bool missing[kBoneCount] = {};  // a bone a left-out shape needs
  const auto leaveOut = [&](const Rule& rule) {
    skipped += skipped.empty() ? "" : ", ";
    skipped += rule.name;
  };
  for (const Rule& rule : kRules) {
    if (std::find(body.omit.begin(), body.omit.end(), rule.name) != body.omit.end()) continue;
    if (rest[rule.carrier] == nullptr || rest[rule.from] == nullptr || rest[rule.to] == nullptr) {
      for (Bone b : {rule.carrier, rule.from, rule.to}) missing[b] = missing[b] || rest[b] == nullptr;
      leaveOut(rule);
      continue;
    }
    const glm::mat4 carrier = toGlm(*rest[rule.carrier]);
    glm::mat4 to_local;
    const glm::vec3 from = position(rule.from), segment = position(rule.to) - from;
    const float length = glm::length(segment);
    const float carrier_scale = largestAxisScale(carrier);
    if (!(length > kMinSegment) || !std::isfinite(length) || !affineInverse(carrier, to_local) ||
        !(carrier_scale > 0.0f)) {
      leaveOut(rule);
      continue;
    }
    const glm::vec3 u = segment / length;
    glm::vec3 start = from, end = from + segment;
    if (rule.kind != Kind::kAlong) start = end = from + u * (rule.along * length);
    if (rule.kind == Kind::kAcross) {
      // The avatar's left at rest, square to the segment.
      glm::vec3 left = glm::vec3(1, 0, 0) - u * u.x;
      if (glm::length(left) < 1e-3f) left = glm::cross(u, glm::vec3(0, 0, 1));
      left = glm::normalize(left) * (rule.half_width * length);
      start -= left;
      end += left;
    }
    ColliderSpec spec;
    spec.node = kBoneNames[rule.carrier];
    spec.shape = rule.kind == Kind::kSphere ? Collider::Shape::kSphere : Collider::Shape::kCapsule;
    spec.offset = fromGlm(glm::vec3(to_local * glm::vec4(start, 1.0f)));
    spec.tail = fromGlm(glm::vec3(to_local * glm::vec4(end, 1.0f)));
    spec.radius = rule.radius * length / carrier_scale * body.scale;  // x 1 changes no bit
    out.push_back(std::move(spec));
  }
  if (!skipped.empty()) {
    std::string lacks;
    for (int b = 0; b < kBoneCount; ++b) {
      if (!missing[b]) continue;
      lacks += lacks.empty() ? "" : ", ";
      lacks += kBoneNames[b];
    }
    std::string message = "dcl-body colliders: left out " + skipped;
    message += lacks.empty() ? " (their bones sit on each other in the rest pose)"
                             : std::string(from_avatar ? " (the avatar lacks " : " (the GLB lacks ") + lacks + ")";
    warnings.push_back(Warning{"body-collider-skipped", std::move(message), ""});
  }
  return out;
}

}  // namespace springbones
