// Angle limits (VRMC_springBone_limit 1.0-draft) as a file or loadRig's options give them: reading
// the limit object, the joint-level extension of a VRMC_springBone joint, and the draft's ranges.
// The rules, with their warnings, are docs/semantics.md's "Angle limits". They read typed input
// (common/typed_value.h), whichever front end produced it.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "common/typed_value.h"
#include "springbones/springbones.h"

namespace springbones {

/// Reads a limit object, `{cone: {angle, rotation?}}`, `{hinge: {angle, rotation?}}` or
/// `{spherical: {pitch, yaw, rotation?}}` (the older draft's `phi` and `theta` for pitch and yaw),
/// into `out` as given (not clamped: sanitizeJointLimit does that). A missing or non-numeric angle
/// is left NaN, for sanitizeJointLimit to warn about. Returns false, with `why`, when the value
/// holds no limit shape, or more than one (UniVRM's rule: such a limit is ignored, not guessed at).
bool readLimitShape(const TypedValue& limit, JointLimit& out, std::string& why);

/// Puts a limit's values into the draft's ranges: cone and hinge angle and spherical pitch in
/// [0, pi], yaw in [0, pi / 2] (NaN, a missing value: the maximum, which leaves that angle free); a
/// rotation that is not 4 finite numbers (within float's range) or has zero length becomes the identity,
/// any other is made unit in double precision, whatever its finite size. Each change leaves a warning (`limit-clamped`,
/// `limit-rotation-invalid`) naming `label` at `path`. Returns false (and sets kind kNone) for kind kNone.
bool sanitizeJointLimit(JointLimit& limit, const std::string& label, const std::string& path,
                        std::vector<Warning>& warnings);

/// The VRMC_springBone_limit extension of a VRMC_springBone joint (`joint` is the joint object,
/// `joint_path` its JSON pointer): reads, checks the specVersion ("1.0-draft", or "1.0") and
/// sanitizes it into `out`. No extension: kNone, no warning. One that cannot be used: kNone and a
/// warning (`limit-invalid`, `limit-spec-version`).
void readVrmJointLimit(const TypedValue& joint, const std::string& joint_path, const std::string& label,
                       JointLimit& out, std::vector<Warning>& warnings);

/// Whether a VRMC_springBone joint object carries the VRMC_springBone_limit extension (the last joint
/// of a spring is only a tail: a limit there is ignored with a warning, `limit-on-end-joint`).
bool hasVrmJointLimit(const TypedValue& joint);

/// loadRig's `limits` option: an object from joint node names to limit objects. Reads each entry
/// as given (readLimitShape) into `out`; the rig builder sanitizes them and warns. Returns false,
/// with `why`, when `limits` is not an object or an entry is not a limit object.
bool readLimitOptions(const TypedValue& limits, std::map<std::string, JointLimit>& out, std::string& why);

/// Puts RigOptions::limits on the rig's joints by node name (every joint of that name), each
/// sanitized once. A name that is only a chain's tip (a tail, no joint): `limit-on-end-joint`; a
/// name that is no joint at all: `limit-joint-not-found`; both dropped.
void applyLimitOptions(const std::map<std::string, JointLimit>& limits, Rig& rig);

}  // namespace springbones
