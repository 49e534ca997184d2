// Reading angle limits (see vrm_limits.h; the rules: docs/semantics.md, "Angle limits").
#include "loading/vrm_limits.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "common/glm_interop.h"
#include "common/message_number.h"
#include "common/shown_name.h"

namespace springbones {
namespace {

using json = TypedValue;

constexpr float kPi = 3.14159265358979f;
constexpr float kHalfPi = 1.57079632679490f;
constexpr float kUnset = std::numeric_limits<float>::quiet_NaN();

// A number as a float: non-numbers are NaN (sanitizeJointLimit's "missing"), a double beyond
// float's range becomes an infinity of its sign (then clamped like any value beyond the maximum;
// the conversion itself would be undefined).
float toFloat(const json& value) {
  if (!value.is_number()) return kUnset;
  const double v = value.get<double>();
  constexpr double kMax = std::numeric_limits<float>::max();
  if (v > kMax) return std::numeric_limits<float>::infinity();
  if (v < -kMax) return -std::numeric_limits<float>::infinity();
  return static_cast<float>(v);
}

float readAngle(const json& shape, const char* key) {
  auto it = shape.find(key);
  return it == shape.end() ? kUnset : toFloat(*it);
}

// The rotation as given; one that is not 4 numbers is all NaN (sanitizeJointLimit warns).
Quat readRotation(const json& shape) {
  auto it = shape.find("rotation");
  if (it == shape.end()) return Quat{};
  float v[4];
  if (!it->is_array() || it->size() != 4) return Quat{kUnset, kUnset, kUnset, kUnset};
  for (std::size_t i = 0; i < 4; ++i) { v[i] = toFloat((*it)[i]); }
  return Quat{v[0], v[1], v[2], v[3]};
}

void warn(std::vector<Warning>& warnings, const char* code, std::string message, std::string path) {
  warnings.push_back(Warning{code, std::move(message), std::move(path)});
}

// One angle into [0, max]: NaN (missing, not a number) takes the maximum.
float clampAngle(float value, float max, const char* name, const std::string& label, const std::string& path,
                 std::vector<Warning>& warnings) {
  if (std::isnan(value)) {
    warn(warnings, "limit-clamped",
         label + ": limit " + name + " is missing or not a number; using " + numberText(max, NumberStyle::kFixed) +
             " (no bound)",
         path);
    return max;
  }
  if (value < 0.0f || value > max) {
    const float clamped = value < 0.0f ? 0.0f : max;
    warn(warnings, "limit-clamped",
         label + ": limit " + name + " " + numberText(value, NumberStyle::kFixed) + " is outside [0, " +
             numberText(max, NumberStyle::kFixed) + "]; using " + numberText(clamped, NumberStyle::kFixed),
         path);
    return clamped;
  }
  return value;
}

}  // namespace

bool readLimitShape(const json& limit, JointLimit& out, std::string& why) {
  out = JointLimit{};
  why.clear();
  if (!limit.is_object()) {
    why = "the limit is not an object";
    return false;
  }
  static const char* const kKinds[] = {"cone", "hinge", "spherical"};
  std::optional<TypedValue> shape;
  int found = 0;
  for (int k = 0; k < 3; ++k) {
    auto it = limit.find(kKinds[k]);
    if (it == limit.end()) continue;
    if (!it->is_object()) {
      why = std::string("the limit's ") + kKinds[k] + " is not an object";
      return false;
    }
    if (found++ > 0) {
      // UniVRM's import rule (its issue #2828): a limit with two shapes is ignored, not guessed at.
      why = "the limit has more than one of cone, hinge and spherical";
      return false;
    }
    shape = *it;
    out.kind = k == 0 ? JointLimit::Kind::kCone : k == 1 ? JointLimit::Kind::kHinge : JointLimit::Kind::kSpherical;
  }
  if (!shape) {
    why = "the limit has none of cone, hinge and spherical";
    return false;
  }
  if (out.kind == JointLimit::Kind::kSpherical) {
    // The draft renamed phi and theta to pitch and yaw; files written before still say phi/theta.
    out.pitch = shape->find("pitch") != shape->end() ? readAngle(*shape, "pitch") : readAngle(*shape, "phi");
    out.yaw = shape->find("yaw") != shape->end() ? readAngle(*shape, "yaw") : readAngle(*shape, "theta");
  } else {
    out.angle = readAngle(*shape, "angle");
  }
  out.rotation = readRotation(*shape);
  return true;
}

bool sanitizeJointLimit(JointLimit& limit, const std::string& label, const std::string& path,
                        std::vector<Warning>& warnings) {
  switch (limit.kind) {
    case JointLimit::Kind::kNone: return false;
    case JointLimit::Kind::kCone:
    case JointLimit::Kind::kHinge: limit.angle = clampAngle(limit.angle, kPi, "angle", label, path, warnings); break;
    case JointLimit::Kind::kSpherical:
      limit.pitch = clampAngle(limit.pitch, kPi, "pitch", label, path, warnings);
      limit.yaw = clampAngle(limit.yaw, kHalfPi, "yaw", label, path, warnings);
      break;
  }
  // Made unit in double after dividing by the largest component, as plane normals and the wind are:
  // squared in float, [1e20, 0, 0, 1e20] would overflow and [1e-25, 0, 0, 1e-25] underflow to 0.
  double q[4] = {limit.rotation.x, limit.rotation.y, limit.rotation.z, limit.rotation.w};
  const double largest = std::max({std::fabs(q[0]), std::fabs(q[1]), std::fabs(q[2]), std::fabs(q[3])});
  if (!(largest > 0.0) || !std::isfinite(largest)) {  // NaN fails the first test
    warn(warnings, "limit-rotation-invalid",
         label +
             ": limit rotation is not 4 numbers, finite and within float's range, of a non-zero quaternion; using "
             "the identity",
         path);
    limit.rotation = Quat{};
  } else {
    double scaled_length = 0.0;
    for (double& c : q) {
      c /= largest;
      scaled_length += c * c;
    }
    scaled_length = std::sqrt(scaled_length);
    const double length = largest * scaled_length;
    // The draft requires a unit quaternion; one off by rounding is made unit quietly, one that is not
    // is named, since its author may have meant something else.
    if (std::fabs(length - 1.0) > 1e-3) {
      warn(warnings, "limit-rotation-invalid",
           label + ": limit rotation has length " + numberText(length, NumberStyle::kG6) + ", not 1; it is made unit",
           path);
    }
    limit.rotation = Quat{static_cast<float>(q[0] / scaled_length), static_cast<float>(q[1] / scaled_length),
                          static_cast<float>(q[2] / scaled_length), static_cast<float>(q[3] / scaled_length)};
  }
  return true;
}

bool hasVrmJointLimit(const json& joint) {
  if (!joint.is_object()) return false;
  auto extensions = joint.find("extensions");
  return extensions != joint.end() && extensions->is_object() &&
         extensions->find("VRMC_springBone_limit") != extensions->end();
}

void readVrmJointLimit(const json& joint, const std::string& joint_path, const std::string& label, JointLimit& out,
                       std::vector<Warning>& warnings) {
  out = JointLimit{};
  if (!hasVrmJointLimit(joint)) return;
  const TypedValue extension = *(*joint.find("extensions")).find("VRMC_springBone_limit");
  const std::string path = joint_path + "/extensions/VRMC_springBone_limit";
  if (!extension.is_object()) {
    warn(warnings, "limit-invalid", label + ": VRMC_springBone_limit is not an object; no limit", path);
    return;
  }
  // "1.0-draft" is the draft's; "1.0" is read alike for when it is ratified. Another version may
  // mean other rules, so its limit is not guessed at.
  auto version = extension.find("specVersion");
  std::string spec_version = version != extension.end() && version->is_string() ? version->get<std::string>() : "";
  if (spec_version != "1.0-draft" && spec_version != "1.0") {
    warn(warnings, "limit-spec-version",
         label + ": VRMC_springBone_limit specVersion " +
             (spec_version.empty() ? std::string("is missing") : "'" + spec_version.substr(0, 32) + "' is unknown") +
             "; no limit",
         path + "/specVersion");
    return;
  }
  auto limit = extension.find("limit");
  std::string why;
  if (limit == extension.end()) {
    warn(warnings, "limit-invalid", label + ": VRMC_springBone_limit has no limit; no limit", path);
    return;
  }
  if (!readLimitShape(*limit, out, why)) {
    out = JointLimit{};
    warn(warnings, "limit-invalid", label + ": " + why + "; no limit", path + "/limit");
    return;
  }
  sanitizeJointLimit(out, label, path + "/limit", warnings);
}

bool readLimitOptions(const json& limits, std::map<std::string, JointLimit>& out, std::string& why) {
  out.clear();
  if (!limits.is_object()) {
    why = "limits is not an object of joint names";
    return false;
  }
  for (auto it = limits.begin(); it != limits.end(); ++it) {
    JointLimit limit;
    std::string problem;
    if (!readLimitShape(*it, limit, problem)) {
      why = "limits['" + shownName(it.key()) + "']: " + problem;
      out.clear();
      return false;
    }
    out[it.key()] = limit;
  }
  return true;
}

void applyLimitOptions(const std::map<std::string, JointLimit>& limits, Rig& rig) {
  if (limits.empty()) return;
  const auto& nodes = rig.skeleton.nodes;
  const auto nameOf = [&](int node) -> const std::string* {
    return node >= 0 && static_cast<std::size_t>(node) < nodes.size() ? &nodes[node].name : nullptr;
  };
  std::map<std::string, JointLimit> sanitized;  // per name, warned about once
  for (Joint& joint : rig.joints) {
    const std::string* name = nameOf(joint.node);
    if (name == nullptr) continue;
    auto it = limits.find(*name);
    if (it == limits.end()) continue;
    auto done = sanitized.find(*name);
    if (done == sanitized.end()) {
      JointLimit limit = it->second;
      sanitizeJointLimit(limit, "joint '" + shownName(*name) + "'", "", rig.warnings);
      done = sanitized.emplace(*name, limit).first;
    }
    joint.limit = done->second;
  }
  for (const auto& [name, limit] : limits) {
    if (sanitized.count(name) != 0) continue;
    bool tip = false;
    for (const Joint& joint : rig.joints) {
      const std::string* tail = nameOf(joint.tail_node);
      if (tail != nullptr && *tail == name) tip = true;
    }
    const std::string what = "limit for '" + shownName(name) + "': ";
    if (tip) {
      rig.warnings.push_back(
          Warning{"limit-on-end-joint", what + "the node is a chain's tip, a tail only; ignored", ""});
    } else {
      rig.warnings.push_back(Warning{"limit-joint-not-found", what + "no simulated joint has that name; ignored", ""});
    }
  }
}

}  // namespace springbones
