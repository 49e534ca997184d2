// Deploy-time validator for data.springBones. The schema part follows what Ajv 8 generates for
// @dcl/schemas' SpringBonesData (allErrors, strictNumbers): the order of keywords inside a schema
// (required, additionalProperties, properties; maxItems, minItems, items; maximum, minimum), the
// order JavaScript walks object keys in, and the message texts, so that error lists compare
// one-to-one with the catalyst's. The cross-checks follow the newest core-libs content validator.
#include "creator_tools/validation.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/json_pointer.h"
#include "common/utf8_append.h"
#include "creator_tools/tool_json.h"
#include "loading/bone_params.h"

namespace springbones {
namespace {

using nlohmann::json;

// formatErrorField in the content validator shortens fields longer than this many UTF-16 units.
constexpr std::size_t kCatalystFieldLimit = 100;

// ---------------------------------------------------------------------------------------------
// JSON values as Ajv sees them

// Ajv's strictNumbers: a number must be finite. A json built in C++ may hold NaN or infinities,
// JSON text cannot, so this is where they are rejected.
bool isFiniteNumber(const json& value) {
  if (value.is_number_integer()) return true;  // int64 and uint64
  return value.is_number_float() && std::isfinite(value.get<double>());
}

bool isInteger(const json& value) {
  if (value.is_number_integer()) return true;
  if (!isFiniteNumber(value)) return false;
  const double x = value.get<double>();
  return std::floor(x) == x;  // 1.0 is an integer, as in JavaScript
}

// enum: [1] compares with ===, so 1.0 matches and "1" or true do not.
bool isNumberOne(const json& value) {
  if (value.is_number_unsigned()) return value.get<std::uint64_t>() == 1;
  if (value.is_number_integer()) return value.get<std::int64_t>() == 1;
  return value.is_number_float() && value.get<double>() == 1.0;
}

// JavaScript's "array index" keys: "0" .. "4294967294" without leading zeros.
bool isArrayIndexKey(const std::string& key) {
  if (key.empty() || key.size() > 10) return false;
  if (key.size() > 1 && key[0] == '0') return false;
  std::uint64_t value = 0;
  for (char c : key) {
    if (c < '0' || c > '9') return false;
    value = value * 10 + static_cast<std::uint64_t>(c - '0');
  }
  return value < 4294967295ull;
}

// The order in which JavaScript enumerates an object's keys: array-index keys ascending, then the
// other keys in insertion order. nlohmann::json keeps keys sorted, so insertion order is gone;
// sorted order stands in for it (documents whose keys were written sorted match exactly).
std::vector<json::const_iterator> keysInJavaScriptOrder(const json& object) {
  std::vector<json::const_iterator> index_keys;
  std::vector<json::const_iterator> other_keys;
  for (auto it = object.cbegin(); it != object.cend(); ++it) {
    (isArrayIndexKey(it.key()) ? index_keys : other_keys).push_back(it);
  }
  // Without leading zeros, numeric order is shorter-first, then lexicographic.
  std::sort(index_keys.begin(), index_keys.end(), [](const json::const_iterator& a, const json::const_iterator& b) {
    const std::string& ka = a.key();
    const std::string& kb = b.key();
    return ka.size() != kb.size() ? ka.size() < kb.size() : ka < kb;
  });
  index_keys.insert(index_keys.end(), other_keys.begin(), other_keys.end());
  return index_keys;
}

// Limits are small integers; printed the way JavaScript prints them ("4", "-10").
std::string formatLimit(double limit) {
  if (std::floor(limit) == limit && std::fabs(limit) < 1e15) { return std::to_string(static_cast<long long>(limit)); }
  return std::to_string(limit);
}

// ---------------------------------------------------------------------------------------------
// The schema, keyword by keyword

class SchemaChecker {
 public:
  explicit SchemaChecker(std::vector<ValidationError>& errors) : errors_(errors) {}

  void checkRoot(const json& root) {
    if (!root.is_object()) {
      fail("", "must be object");
      return;
    }
    auto version = root.find("version");
    auto models = root.find("models");
    if (version == root.end()) fail("", "must have required property 'version'");
    if (models == root.end()) fail("", "must have required property 'models'");
    // One error per extra key, all with the same path and text.
    for (auto it = root.begin(); it != root.end(); ++it) {
      if (it.key() != "version" && it.key() != "models") { fail("", "must NOT have additional properties"); }
    }
    if (version != root.end()) {
      // type and enum are independent keywords: "1" and 1.5 fail both.
      if (!isInteger(*version)) fail("/version", "must be integer");
      if (!isNumberOne(*version)) fail("/version", "must be equal to one of the allowed values");
    }
    if (models != root.end()) checkModels(*models);
  }

 private:
  void checkModels(const json& models) {
    if (!models.is_object()) {
      fail("/models", "must be object");
      return;
    }
    for (const auto& model : keysInJavaScriptOrder(models)) {
      const std::string model_path = "/models" + pointerToken(model.key());
      if (!model->is_object()) {
        fail(model_path, "must be object");
        continue;
      }
      for (const auto& bone : keysInJavaScriptOrder(*model)) {
        checkBone(*bone, model_path + pointerToken(bone.key()));
      }
    }
  }

  void checkBone(const json& bone, const std::string& path) {
    if (!bone.is_object()) {
      fail(path, "must be object");
      return;
    }
    static const char* const kRequired[] = {"stiffness", "gravityPower", "gravityDir", "drag"};
    for (const char* key : kRequired) {
      if (bone.find(key) == bone.end()) { fail(path, std::string("must have required property '") + key + "'"); }
    }
    // Unknown keys are allowed here: the bone schema has no additionalProperties.
    checkRange(bone, kStiffnessRange.key, kStiffnessRange.min, kStiffnessRange.max, path);
    checkRange(bone, kGravityPowerRange.key, kGravityPowerRange.min, kGravityPowerRange.max, path);
    auto gravity_dir = bone.find("gravityDir");
    if (gravity_dir != bone.end()) checkGravityDir(*gravity_dir, path + "/gravityDir");
    checkRange(bone, kDragRange.key, kDragRange.min, kDragRange.max, path);
    auto center = bone.find("center");
    if (center != bone.end() && !center->is_string() && !center->is_null()) {
      fail(path + "/center", "must be string");  // nullable: the message names only the type
    }
    auto is_root = bone.find("isRoot");
    if (is_root != bone.end() && !is_root->is_boolean() && !is_root->is_null()) {
      fail(path + "/isRoot", "must be boolean");
    }
  }

  void checkRange(const json& bone, std::string_view key, double min, double max, const std::string& bone_path) {
    auto it = bone.find(std::string(key));
    if (it == bone.end()) return;
    checkNumber(*it, min, max, bone_path + "/" + std::string(key));
  }

  void checkNumber(const json& value, double min, double max, const std::string& path) {
    if (!isFiniteNumber(value)) {
      fail(path, "must be number");
      return;
    }
    const double x = value.get<double>();
    if (x > max) fail(path, "must be <= " + formatLimit(max));
    if (x < min) fail(path, "must be >= " + formatLimit(min));
  }

  void checkGravityDir(const json& value, const std::string& path) {
    if (!value.is_array()) {
      fail(path, "must be array");
      return;
    }
    if (value.size() > 3) fail(path, "must NOT have more than 3 items");
    if (value.size() < 3) fail(path, "must NOT have fewer than 3 items");
    // A tuple schema: only the first three items are checked, whatever the length.
    const double limit = kGravityDirComponentLimit;
    for (std::size_t i = 0; i < value.size() && i < 3; ++i) {
      checkNumber(value[i], -limit, limit, path + "/" + std::to_string(i));
    }
  }

  void fail(std::string path, std::string message) {
    errors_.push_back(ValidationError{std::move(path), std::move(message)});
  }

  std::vector<ValidationError>& errors_;
};

// ---------------------------------------------------------------------------------------------
// The catalyst's way of quoting a field in a message: JSON.stringify(field) without the opening
// quote, cut to the field's own length (or to 99 units plus "..." past 100). Lengths and cuts are
// in UTF-16 code units, so the text is converted to UTF-16 and back.

std::u16string toUtf16(const std::string& text) {
  std::u16string out;
  out.reserve(text.size());
  std::size_t i = 0;
  while (i < text.size()) {
    const auto lead = static_cast<unsigned char>(text[i]);
    if (lead < 0x80) {
      out.push_back(lead);
      ++i;
      continue;
    }
    std::size_t extra = 0;
    char32_t cp = 0;
    if (lead >= 0xC2 && lead <= 0xDF) {
      extra = 1;
      cp = lead & 0x1Fu;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
      extra = 2;
      cp = lead & 0x0Fu;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
      extra = 3;
      cp = lead & 0x07u;
    } else {
      out.push_back(u'\uFFFD');  // a json built in C++ may hold bytes that are not UTF-8
      ++i;
      continue;
    }
    bool ok = i + extra < text.size();
    for (std::size_t k = 1; ok && k <= extra; ++k) {
      const auto cont = static_cast<unsigned char>(text[i + k]);
      ok = (cont & 0xC0u) == 0x80u;
      cp = (cp << 6) | (cont & 0x3Fu);
    }
    // Overlong forms, surrogates and values past U+10FFFF are not UTF-8 either.
    if (ok && ((extra == 2 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) ||
               (extra == 3 && (cp < 0x10000 || cp > 0x10FFFF)))) {
      ok = false;
    }
    if (!ok) {
      out.push_back(u'\uFFFD');
      ++i;
      continue;
    }
    if (cp >= 0x10000) {
      cp -= 0x10000;
      out.push_back(static_cast<char16_t>(0xD800 + (cp >> 10)));
      out.push_back(static_cast<char16_t>(0xDC00 + (cp & 0x3FF)));
    } else {
      out.push_back(static_cast<char16_t>(cp));
    }
    i += extra + 1;
  }
  return out;
}


// A cut can split a surrogate pair; the lone half has no UTF-8 form and becomes U+FFFD.
std::string toUtf8(const std::u16string& units) {
  std::string out;
  out.reserve(units.size());
  for (std::size_t i = 0; i < units.size(); ++i) {
    const char16_t u = units[i];
    if (u >= 0xD800 && u <= 0xDBFF && i + 1 < units.size() && units[i + 1] >= 0xDC00 && units[i + 1] <= 0xDFFF) {
      appendUtf8(
          out, 0x10000 + ((static_cast<char32_t>(u) - 0xD800) << 10) + (static_cast<char32_t>(units[i + 1]) - 0xDC00));
      ++i;
    } else if (u >= 0xD800 && u <= 0xDFFF) {
      appendUtf8(out, 0xFFFD);
    } else {
      appendUtf8(out, u);
    }
  }
  return out;
}

// JSON.stringify of a string, in UTF-16 units.
std::u16string quoteAsJavaScript(const std::u16string& text) {
  static const char16_t kHex[] = u"0123456789abcdef";
  std::u16string out;
  out.reserve(text.size() + 2);
  out += u'"';
  for (char16_t c : text) {
    switch (c) {
      case u'"': out += u"\\\""; break;
      case u'\\': out += u"\\\\"; break;
      case u'\b': out += u"\\b"; break;
      case u'\f': out += u"\\f"; break;
      case u'\n': out += u"\\n"; break;
      case u'\r': out += u"\\r"; break;
      case u'\t': out += u"\\t"; break;
      default:
        if (c < 0x20) {
          out += u"\\u00";
          out += kHex[c >> 4];
          out += kHex[c & 0xF];
        } else {
          out += c;
        }
    }
  }
  out += u'"';
  return out;
}

std::string catalystField(const std::string& field) {
  const std::u16string units = toUtf16(field);
  const std::u16string quoted = quoteAsJavaScript(units);
  if (units.size() > kCatalystFieldLimit) { return toUtf8(quoted.substr(1, kCatalystFieldLimit - 1)) + "..."; }
  // Cut at the raw length, so a field with escapes loses its tail (as the catalyst's does).
  return toUtf8(quoted.substr(1, units.size()));
}

// ---------------------------------------------------------------------------------------------
// The entity

const json* findMember(const json& object, const char* key) {
  if (!object.is_object()) return nullptr;
  auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

bool isAbsent(const json* value) { return value == nullptr || value->is_null(); }

// Where a subject keeps its parts. A catalyst entity: {content: [{file, hash}], metadata: {data}};
// a Builder item: {contents: {file: hash}, data}. Both carry representations and springBones in
// their data, and both are validated alike.
struct Subject {
  const json* data = nullptr;
  std::string data_path;  ///< JSON pointer of data inside the subject
  std::string data_name;  ///< how messages name data ("entity metadata.data", "item data")
  bool is_item = false;
};

// The shape of the subject, or false for a value that is neither form: reading such a value as
// "no springBones" would answer "valid" for something the validator never read.
bool readSubject(const json& subject, Subject& out) {
  if (!subject.is_object()) return false;
  const json* metadata = findMember(subject, "metadata");
  if (metadata != nullptr && metadata->is_object()) {
    const json* data = findMember(*metadata, "data");
    if (data != nullptr && data->is_object()) {
      out = Subject{data, "/metadata/data", "entity metadata.data", false};
      return true;
    }
  }
  const json* data = findMember(subject, "data");
  if (data != nullptr && data->is_object() && !isAbsent(findMember(subject, "contents"))) {
    out = Subject{data, "/data", "item data", true};
    return true;
  }
  return false;
}

// Content hashes by file name, the first entry of a file winning as Array.prototype.find does;
// false (with errors) when the list cannot be read.
bool readContentHashes(const json& subject, bool is_item,
                       std::unordered_map<std::string, const std::string*>& hash_of_file,
                       std::vector<ValidationError>& errors) {
  if (is_item) {
    const json& contents = *findMember(subject, "contents");
    if (!contents.is_object()) {
      errors.push_back({"/contents", "item contents must be an object of file: hash"});
      return false;
    }
    for (auto it = contents.begin(); it != contents.end(); ++it) {
      if (!it->is_string()) {
        errors.push_back({"/contents" + pointerToken(it.key()), "item contents value must be a hash string"});
        continue;
      }
      hash_of_file.emplace(it.key(), &it->get_ref<const std::string&>());
    }
    return true;
  }
  const json* content = findMember(subject, "content");
  if (content == nullptr || !content->is_array()) {
    errors.push_back({"/content", "entity content must be an array of {file, hash}"});
    return false;
  }
  for (std::size_t i = 0; i < content->size(); ++i) {
    const json* file = findMember((*content)[i], "file");
    const json* hash = findMember((*content)[i], "hash");
    if (file == nullptr || !file->is_string() || hash == nullptr || !hash->is_string()) {
      errors.push_back(
          {"/content/" + std::to_string(i), "entity content entry must be an object with string file and hash"});
      continue;
    }
    hash_of_file.emplace(file->get_ref<const std::string&>(), &hash->get_ref<const std::string&>());
  }
  return true;
}

std::vector<ValidationError> validateSubject(const json& subject_json, const Subject& subject) {
  std::vector<ValidationError> errors;
  // Only springBones is this validator's business: data without one is fine here.
  const json* spring_bones = findMember(*subject.data, "springBones");
  if (isAbsent(spring_bones)) return errors;

  std::vector<ValidationError> schema_errors = validateSpringBonesSchema(*spring_bones);
  if (!schema_errors.empty()) {
    for (ValidationError& e : schema_errors) { e.message = "springBones" + catalystField(e.path) + " " + e.message; }
    return schema_errors;
  }

  // The hashes that current representations load: each mainFile's entry in the content list.
  // Other content (textures, a GLB listed only in contents) does not count. Looked up by name,
  // so many representations over a long content list stay linear.
  std::unordered_set<std::string> active_hashes;
  std::unordered_map<std::string, const std::string*> hash_of_file;
  bool hashes_known = readContentHashes(subject_json, subject.is_item, hash_of_file, errors);
  const std::string representations_path = subject.data_path + "/representations";
  const json* representations = findMember(*subject.data, "representations");
  if (representations == nullptr || !representations->is_array()) {
    errors.push_back({representations_path, subject.data_name + ".representations must be an array"});
    hashes_known = false;
  } else {
    for (std::size_t i = 0; i < representations->size(); ++i) {
      const json* main_file = findMember((*representations)[i], "mainFile");
      if (main_file == nullptr || !main_file->is_string()) {
        errors.push_back({representations_path + "/" + std::to_string(i),
                          (subject.is_item ? "item" : "entity") +
                              std::string(" representation must be an object with a string mainFile")});
        continue;
      }
      if (!hashes_known) continue;
      if (auto it = hash_of_file.find(main_file->get_ref<const std::string&>()); it != hash_of_file.end()) {
        active_hashes.insert(*it->second);
      }
    }
  }

  // The schema passed, so models is an object of objects.
  const json& models = *findMember(*spring_bones, "models");
  for (const auto& model : keysInJavaScriptOrder(models)) {
    const std::string& hash = model.key();
    const std::string model_path = "/models" + pointerToken(hash);
    // Without the entity's hashes every key would look stale; the structure error says enough.
    if (hashes_known && active_hashes.count(hash) == 0) {
      errors.push_back({model_path, "springBones.models key " + catalystField(hash) +
                                        " does not match any current representation hash"});
    }
    for (const auto& bone : keysInJavaScriptOrder(*model)) {
      // The Builder and the catalyst lower-case the name with JavaScript's toLowerCase and look for
      // the token; isSpringBoneName's ASCII folding answers the same, as no other character
      // lower-cases to one of the token's letters on its own (U+0130 becomes "i" and a combining dot).
      if (!isSpringBoneName(bone.key())) {
        errors.push_back({model_path + pointerToken(bone.key()),
                          "Bone name " + catalystField(bone.key()) + " in model " + catalystField(hash) +
                              " does not follow the spring bone naming convention"});
      }
    }
  }
  return errors;
}

// Nothing above throws on any json; this only guards against running out of memory. It must not
// answer "valid", so if even this small vector cannot be built, bad_alloc goes to the caller.
std::vector<ValidationError> internalFailure() {
  return {ValidationError{"", "validation could not complete (out of memory)"}};
}

}  // namespace

std::vector<ValidationError> validateSpringBonesSchema(const json& springBones) {
  try {
    std::vector<ValidationError> errors;
    SchemaChecker(errors).checkRoot(springBones);
    return errors;
  } catch (...) { return internalFailure(); }
}

Error validateSpringBones(const json& subject, std::vector<ValidationError>& errors) {
  errors.clear();
  try {
    Subject parts;
    if (!readSubject(subject, parts)) {
      return Error{ErrorCode::kInvalidArgument,
                   "validateSpringBones reads a catalyst entity {content, metadata: {data: {representations, "
                   "springBones}}} or a Builder item {contents, data: {representations, springBones}}; this "
                   "is neither",
                   ""};
    }
    errors = validateSubject(subject, parts);
  } catch (...) { errors = internalFailure(); }
  return {};
}

ApiFailure validateSpringBones(std::string_view entity_text, const std::string& marker, std::string& errors_json) {
  errors_json.clear();
  json entity;
  if (ApiFailure f = parseArgument(entity_text, "entity", entity)) return f;
  restoreNonFinite(entity, marker);
  std::vector<ValidationError> errors;
  if (Error e = validateSpringBones(entity, errors)) return toFailure(e);
  errors_json = validationErrorsJson(errors);
  return {};
}

}  // namespace springbones
