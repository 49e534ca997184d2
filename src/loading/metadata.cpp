// Reading data.springBones for the runtime: forgiving where the deploy-time validator is strict.
// A preview must show whatever the catalyst accepted, and should still show something sensible
// for metadata it would reject, so every problem here is a warning with a fallback, except shapes
// that leave nothing to read (springBones or models[hash] not an object). One reader, on typed
// values: the page's parsed object and the readers' parse of a text reach the same code.
#include "loading/metadata.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "common/json_pointer.h"
#include "common/message_number.h"
#include "common/quoted_value.h"
#include "common/shown_name.h"
#include "loading/bone_params.h"
#include "springbones/springbones.h"

namespace springbones {
namespace {

std::string describe(const TypedValue& value) { return quoteValue(value, 60); }

std::string format(float v) { return numberText(v, NumberStyle::kFixedTrim); }

std::string missingMessage(const ParamRange& range) {
  return std::string(range.key) + " is missing; using the default " + format(range.fallback);
}
constexpr const char* kGravityDirMissing = "gravityDir is missing; using the default [0,-1,0]";

bool inRange(double value, const ParamRange& range) { return !(value < range.min || value > range.max); }

// A readable gravityDir (3 finite numbers) as a unit vector; false when it has no direction.
// Divided by the largest component first: squaring [1e200, 0, 0] would overflow to infinity.
bool unitGravityDir(double v[3], Vec3& out) {
  const double largest = std::max({std::fabs(v[0]), std::fabs(v[1]), std::fabs(v[2])});
  if (!(largest > 1e-9)) return false;
  for (int i = 0; i < 3; ++i) v[i] /= largest;
  const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  out = Vec3{static_cast<float>(v[0] / length), static_cast<float>(v[1] / length), static_cast<float>(v[2] / length)};
  return true;
}

class EntryReader {
 public:
  EntryReader(std::vector<Warning>& warnings) : warnings_(warnings) {}

  float readScalar(const TypedValue& entry, const ParamRange& range, const std::string& entry_path) {
    const std::string key(range.key);
    const std::string path = entry_path + pointerToken(key);
    auto it = entry.find(key);
    if (it == entry.end()) {
      warn("param-missing", missingMessage(range), path);
      return range.fallback;
    }
    if (!it->is_number()) {
      warn("param-not-number",
           key + " is " + describe(*it) + ", not a number; using the default " + format(range.fallback), path);
      return range.fallback;
    }
    const double value = it->get<double>();
    if (!std::isfinite(value)) {
      warn("param-not-finite", key + " is not finite; using the default " + format(range.fallback), path);
      return range.fallback;
    }
    if (!inRange(value, range)) {
      const float clamped = value < range.min ? range.min : range.max;
      warn("param-out-of-range",
           key + " " + describe(*it) + " is outside [" + format(range.min) + ", " + format(range.max) +
               "]; clamped to " + format(clamped),
           path);
      return clamped;
    }
    return static_cast<float>(value);
  }

  Vec3 readGravityDir(const TypedValue& entry, const std::string& entry_path) {
    const Vec3 fallback{0.0f, -1.0f, 0.0f};
    const std::string path = entry_path + "/gravityDir";
    auto it = entry.find("gravityDir");
    if (it == entry.end()) {
      warn("param-missing", kGravityDirMissing, path);
      return fallback;
    }
    bool readable = it->is_array() && it->size() == 3;
    double v[3] = {0, 0, 0};
    for (std::size_t i = 0; readable && i < 3; ++i) {
      readable = (*it)[i].is_number() && std::isfinite((*it)[i].get<double>());
      if (readable) v[i] = (*it)[i].get<double>();
    }
    if (!readable) {
      warn("param-not-vector", "gravityDir " + describe(*it) + " is not 3 finite numbers; using the default [0,-1,0]",
           path);
      return fallback;
    }
    for (double c : v) {
      if (std::fabs(c) > kGravityDirComponentLimit) {
        // Only the direction is used, so the value is normalized rather than clamped (clamping
        // a component would turn the vector); the validator still rejects it.
        warn("param-out-of-range",
             "gravityDir " + describe(*it) + " has a component outside [-10, 10]; only its direction is used", path);
        break;
      }
    }
    Vec3 unit;
    if (!unitGravityDir(v, unit)) {
      warn("gravity-dir-zero", "gravityDir has no direction; using the default [0,-1,0]", path);
      return fallback;
    }
    return unit;
  }

  void readCenter(const TypedValue& entry, const std::string& entry_path, BoneEntry& out) {
    auto it = entry.find("center");
    if (it == entry.end()) return;
    if (it->is_null()) {
      out.has_center = true;  // explicitly world space
    } else if (it->is_string()) {
      out.has_center = true;
      out.center = it->get<std::string>();
    } else {
      warn("center-not-string", "center " + describe(*it) + " is not a node name; ignored", entry_path + "/center");
    }
  }

  bool readIsRoot(const TypedValue& entry, const std::string& entry_path) {
    auto it = entry.find("isRoot");
    if (it == entry.end() || it->is_null()) return false;
    if (it->is_boolean()) return it->get<bool>();
    warn("is-root-not-boolean", "isRoot " + describe(*it) + " is not a boolean; treated as false",
         entry_path + "/isRoot");
    return false;
  }

  void warn(const char* code, std::string message, std::string path) {
    warnings_.push_back(Warning{code, std::move(message), std::move(path)});
  }

 private:
  std::vector<Warning>& warnings_;
};

// When `value` (given as springBones) is a whole wearable instead, the warning that says so and
// where its springBones is: a catalyst entity keeps it at metadata.data.springBones, a Builder item
// at data.springBones (the shapes entity.cpp reads). Empty for anything else.
std::string entityMessage(const TypedValue& value) {
  const auto member = [](const TypedValue& object, const char* key) {
    auto it = object.find(key);
    return it == object.end() ? TypedValue() : *it;
  };
  const TypedValue metadata_data = member(member(value, "metadata"), "data");
  const TypedValue item_data = member(value, "data");
  const bool catalyst = metadata_data.is_object();
  if (!catalyst && !(item_data.is_object() && item_data.find("representations") != item_data.end())) return "";
  const TypedValue& data = catalyst ? metadata_data : item_data;
  const std::string where = catalyst ? "metadata.data.springBones" : "data.springBones";
  const std::string what =
      catalyst ? "a wearable entity (it has metadata.data)" : "a Builder item (it has data.representations)";
  const bool has = data.find("springBones") != data.end();
  return "springBones is " + what + ", not its springBones: pass " + (catalyst ? "entity." : "item.") + where +
         " as springBones (" + (has ? "it has one" : "this one has none") +
         ") and the entity as the entity option; spring bones are disabled for this wearable";
}

}  // namespace

Error parseSpringBones(const TypedValue& springBones, const std::string& hash, ModelEntry& out,
                       std::vector<Warning>& warnings) {
  out = ModelEntry{};
  if (springBones.is_null()) return {};
  if (!springBones.is_object()) {
    return Error{ErrorCode::kMetadataInvalid, "springBones is " + describe(springBones) + ", not an object", ""};
  }
  EntryReader reader(warnings);
  auto version = springBones.find("version");
  if (version == springBones.end() || !version->is_number() || version->get<double>() != 1.0) {
    if (std::string entity = entityMessage(springBones); !entity.empty()) {
      reader.warn("unsupported-version", entity, "/version");
      return {};
    }
    reader.warn("unsupported-version",
                "springBones.version is " +
                    (version == springBones.end() ? std::string("missing") : describe(*version)) +
                    ", not 1; spring bones are disabled for this wearable",
                "/version");
    return {};
  }
  auto models = springBones.find("models");
  if (models == springBones.end()) {
    reader.warn("models-missing", "springBones.models is missing; no spring bones", "/models");
    return {};
  }
  if (!models->is_object()) {
    return Error{ErrorCode::kMetadataInvalid, "springBones.models is " + describe(*models) + ", not an object",
                 "/models"};
  }
  auto model = models->find(hash);
  if (model == models->end()) {
    std::string keys;
    for (auto it = models->begin(); it != models->end(); ++it) { keys += (keys.empty() ? "" : ", ") + it.key(); }
    reader.warn("model-not-found",
                "springBones.models has no entry for hash " + hash +
                    (keys.empty() ? std::string(" (it is empty)") : " (it has: " + keys + ")") +
                    "; no spring bones for this GLB",
                "/models" + pointerToken(hash));
    return {};
  }
  const std::string model_path = "/models" + pointerToken(hash);
  if (!model->is_object()) {
    return Error{ErrorCode::kMetadataInvalid,
                 "springBones.models[" + hash + "] is " + describe(*model) + ", not an object", model_path};
  }
  out.enabled = true;
  out.path = model_path;
  out.bones.reserve(model->size());
  for (auto it = model->begin(); it != model->end(); ++it) {
    const std::string path = model_path + pointerToken(it.key());
    if (!it->is_object()) {
      reader.warn("bone-entry-invalid",
                  "entry for '" + shownName(it.key()) + "' is " + describe(*it) + ", not an object; ignored", path);
      continue;
    }
    BoneEntry bone;
    bone.name = it.key();
    bone.params.stiffness = reader.readScalar(*it, kStiffnessRange, path);
    bone.params.gravity_power = reader.readScalar(*it, kGravityPowerRange, path);
    bone.params.gravity_dir = reader.readGravityDir(*it, path);
    bone.params.drag = reader.readScalar(*it, kDragRange, path);
    reader.readCenter(*it, path, bone);
    bone.is_root = reader.readIsRoot(*it, path);
    out.bones.push_back(std::move(bone));
  }
  return {};
}

std::string ModelEntry::entryPath(const BoneEntry& bone) const { return path + pointerToken(bone.name); }

}  // namespace springbones
