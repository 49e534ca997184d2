// Reading data.springBones for the runtime: forgiving where the deploy-time validator is strict.
// A preview must show whatever the catalyst accepted, and should still show something sensible
// for metadata it would reject, so every problem here is a warning with a fallback, except shapes
// that leave nothing to read (springBones or models[hash] not an object).
//
// From text there are two readers (as for the glTF, see glb_loader.cpp): a fast one that scans
// the text once (json_scan.h) and handles the usual document (values present and in range, or
// missing), and the nlohmann-based one for everything else, which also gives the exact error or
// warning text. The fast one gives up, leaving no trace, unless its result is the same.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>

#include "bone_params.h"
#include "json_depth.h"
#include "json_pointer.h"
#include "json_scan.h"
#include "springbones.h"

// See glb_loader.cpp: keeps the destructor-free fast reader out of callers that have cleanups.
#if defined(__GNUC__) || defined(__clang__)
#define SPRINGBONES_NOINLINE __attribute__((noinline))
#else
#define SPRINGBONES_NOINLINE
#endif

namespace springbones {
namespace {

using nlohmann::json;

std::string describe(const json& value) {
  if (nestsDeeperThan(value, 8)) return value.is_array() ? "a deeply nested array" : "a deeply nested object";
  std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return text;
}

std::string format(float v) {
  std::string s = std::to_string(v);
  s.erase(s.find_last_not_of('0') + 1);
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

std::string missingMessage(const ParamRange& range) {
  return std::string(range.key) + " is missing; using the default " + format(range.fallback);
}
constexpr const char* kGravityDirMissing = "gravityDir is missing; using the default [0,-1,0]";

bool inRange(double value, const ParamRange& range) { return !(value < range.min || value > range.max); }

// A readable gravityDir (3 finite numbers) as a unit vector; false when it has no direction.
// Divided by the largest component first: squaring [1e200, 0, 0] would overflow to infinity.
bool unitGravityDir(double v[3], glm::vec3& out) {
  const double largest = std::max({std::fabs(v[0]), std::fabs(v[1]), std::fabs(v[2])});
  if (!(largest > 1e-9)) return false;
  for (int i = 0; i < 3; ++i) v[i] /= largest;
  const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  out = glm::vec3(static_cast<float>(v[0] / length), static_cast<float>(v[1] / length),
                  static_cast<float>(v[2] / length));
  return true;
}

class EntryReader {
 public:
  EntryReader(std::vector<Warning>& warnings) : warnings_(warnings) {}

  float readScalar(const json& entry, const ParamRange& range, const std::string& entry_path) {
    const std::string key(range.key);
    const std::string path = entry_path + pointerToken(key);
    auto it = entry.find(key);
    if (it == entry.end()) {
      warn("param-missing", missingMessage(range), path);
      return range.fallback;
    }
    if (!it->is_number()) {
      warn("param-not-number", key + " is " + describe(*it) + ", not a number; using the default " +
                                   format(range.fallback),
           path);
      return range.fallback;
    }
    const double value = it->get<double>();
    if (!std::isfinite(value)) {
      warn("param-not-finite",
           key + " is not finite; using the default " + format(range.fallback), path);
      return range.fallback;
    }
    if (!inRange(value, range)) {
      const float clamped = value < range.min ? range.min : range.max;
      warn("param-out-of-range", key + " " + describe(*it) + " is outside [" + format(range.min) +
                                     ", " + format(range.max) + "]; clamped to " + format(clamped),
           path);
      return clamped;
    }
    return static_cast<float>(value);
  }

  glm::vec3 readGravityDir(const json& entry, const std::string& entry_path) {
    const glm::vec3 fallback(0.0f, -1.0f, 0.0f);
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
      warn("param-not-vector", "gravityDir " + describe(*it) +
                                   " is not 3 finite numbers; using the default [0,-1,0]",
           path);
      return fallback;
    }
    for (double c : v) {
      if (std::fabs(c) > kGravityDirComponentLimit) {
        // Only the direction is used, so the value is normalized rather than clamped (clamping
        // a component would turn the vector); the validator still rejects it.
        warn("param-out-of-range", "gravityDir " + describe(*it) +
                                       " has a component outside [-10, 10]; only its direction is used",
             path);
        break;
      }
    }
    glm::vec3 unit;
    if (!unitGravityDir(v, unit)) {
      warn("gravity-dir-zero", "gravityDir has no direction; using the default [0,-1,0]", path);
      return fallback;
    }
    return unit;
  }

  void readCenter(const json& entry, const std::string& entry_path, BoneEntry& out) {
    auto it = entry.find("center");
    if (it == entry.end()) return;
    if (it->is_null()) {
      out.has_center = true;  // explicitly world space
    } else if (it->is_string()) {
      out.has_center = true;
      out.center = it->get<std::string>();
    } else {
      warn("center-not-string", "center " + describe(*it) + " is not a node name; ignored",
           entry_path + "/center");
    }
  }

  bool readIsRoot(const json& entry, const std::string& entry_path) {
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

// ---------------------------------------------------------------------------------------------
// The fast reader of springBones text. It handles a document whose version is 1 and whose
// models[hash] is an object of entries that are objects with every present value readable and in
// range (stiffness, gravityPower, drag numbers in their ranges; gravityDir 3 finite numbers in
// [-10, 10] with a direction; center a string or null; isRoot a boolean or null), keys appearing
// once. Anything else returns false and the nlohmann path decides, with its own warnings.

constexpr unsigned kMissStiffness = 1, kMissGravityPower = 2, kMissGravityDir = 4, kMissDrag = 8;

struct ScannedBone {
  BoneEntry entry;       ///< name, params, center, is_root
  unsigned missing = 0;  ///< MissingParam bits: each one is a param-missing warning
};

// The values both fast readers (text and entries) take: those parseSpringBones reads without a
// warning. Anything else is left to it.
bool acceptParam(double value, const ParamRange& range, float& out) {
  if (!std::isfinite(value) || !inRange(value, range)) return false;
  out = static_cast<float>(value);
  return true;
}

bool acceptGravityDirComponent(double value) {
  return std::isfinite(value) && std::fabs(value) <= kGravityDirComponentLimit;
}

// unitGravityDir for the fast readers, remembering the last input: the entries of a wearable
// nearly always share one gravityDir, and its division and square root were a tenth of reading
// them. Same bits in, same bits out, so the result is unitGravityDir's.
class GravityDirs {
 public:
  bool unit(double v[3], glm::vec3& out) {
    // Compared as integers: a memcmp stays a byte loop call in WebAssembly.
    std::uint64_t bits[3];
    std::memcpy(bits, v, sizeof bits);
    if (known_ && bits[0] == last_[0] && bits[1] == last_[1] && bits[2] == last_[2]) {
      out = unit_;
      return true;
    }
    std::memcpy(last_, bits, sizeof last_);
    known_ = unitGravityDir(v, unit_);  // v is scaled in place: last_ keeps the input
    out = unit_;
    return known_;
  }

 private:
  std::uint64_t last_[3] = {0, 0, 0};  ///< the bits of the last input
  glm::vec3 unit_{0.0f};
  bool known_ = false;  ///< last_ had a direction, unit_ is it
};

bool scanParam(JsonScan& scan, const ParamRange& range, float& out) {
  JsonNumber n;
  return scan.number(n) && acceptParam(n.value, range, out);
}

bool scanGravityDir(JsonScan& scan, GravityDirs& dirs, glm::vec3& out) {
  double v[3];
  if (!scan.consume('[')) return false;
  for (int i = 0; i < 3; ++i) {
    JsonNumber n;
    if ((i > 0 && !scan.consume(',')) || !scan.number(n) || !acceptGravityDirComponent(n.value)) return false;
    v[i] = n.value;
  }
  return scan.consume(']') && dirs.unit(v, out);
}

bool scanEntry(JsonScan& scan, ScannedBone& bone, GravityDirs& dirs, std::string& scratch) {
  enum : unsigned { kStiffness = 1, kGravityPower = 2, kGravityDir = 4, kDrag = 8, kCenter = 16, kIsRoot = 32 };
  unsigned seen = 0;
  BoneEntry& entry = bone.entry;
  if (!scan.consume('{')) return false;
  if (!scan.consume('}')) {
    do {
      std::string_view key;
      if (!scan.string(key, scratch) || !scan.consume(':')) return false;
      unsigned field = 0;
      bool ok = true;
      if (keyIs(key, "stiffness")) {
        field = kStiffness;
        ok = scanParam(scan, kStiffnessRange, entry.params.stiffness);
      } else if (keyIs(key, "gravityPower")) {
        field = kGravityPower;
        ok = scanParam(scan, kGravityPowerRange, entry.params.gravity_power);
      } else if (keyIs(key, "drag")) {
        field = kDrag;
        ok = scanParam(scan, kDragRange, entry.params.drag);
      } else if (keyIs(key, "gravityDir")) {
        field = kGravityDir;
        ok = scanGravityDir(scan, dirs, entry.params.gravity_dir);
      } else if (keyIs(key, "center")) {
        field = kCenter;
        entry.has_center = true;
        std::string_view center;
        if (scan.peek() == 'n') {
          ok = scan.word("null");
        } else if ((ok = scan.string(center, scratch))) {
          entry.center = std::string(center.data(), center.size());
        }
      } else if (keyIs(key, "isRoot")) {
        field = kIsRoot;
        const char c = scan.peek();
        ok = c == 't' ? scan.word("true") : c == 'f' ? scan.word("false") : scan.word("null");
        entry.is_root = c == 't';
      } else {
        ok = scan.skipValue(scratch);
      }
      if (!ok || (seen & field)) return false;
      seen |= field;
    } while (scan.consume(','));
    if (!scan.consume('}')) return false;
  }
  bone.missing = ((seen & kStiffness) ? 0 : kMissStiffness) | ((seen & kGravityPower) ? 0 : kMissGravityPower) |
                 ((seen & kGravityDir) ? 0 : kMissGravityDir) | ((seen & kDrag) ? 0 : kMissDrag);
  return true;
}

// The entries of models[hash] in document order, or false.
SPRINGBONES_NOINLINE bool scanSpringBones(std::string_view text, const std::string& hash,
                                          std::vector<ScannedBone>& bones, std::string& scratch) {
  JsonScan scan(text.data(), text.data() + text.size());
  GravityDirs dirs;
  // An entry takes at least 7 bytes ("x":{}, plus a key); one in 64 bytes is usual. Reserving
  // spares the moves of growth (each an out-of-line call at -Oz).
  bones.reserve(std::min<std::size_t>(text.size() / 64, 1 << 16));
  bool seen_version = false, seen_models = false, found = false;
  double version = 0;
  if (!scan.consume('{')) return false;
  if (!scan.consume('}')) {
    do {
      std::string_view key;
      if (!scan.string(key, scratch) || !scan.consume(':')) return false;
      if (keyIs(key, "version")) {
        JsonNumber n;
        if (seen_version || !scan.number(n)) return false;
        seen_version = true;
        version = n.value;
      } else if (keyIs(key, "models")) {
        if (seen_models || !scan.consume('{')) return false;
        seen_models = true;
        if (!scan.consume('}')) {
          do {
            std::string_view model_key;
            if (!scan.string(model_key, scratch) || !scan.consume(':')) return false;
            if (model_key != hash) {
              if (!scan.skipValue(scratch)) return false;
              continue;
            }
            if (found || !scan.consume('{')) return false;
            found = true;
            if (scan.consume('}')) continue;
            do {
              std::string_view name;
              if (!scan.string(name, scratch) || !scan.consume(':')) return false;
              bones.emplace_back();
              // Constructed, not assign()ed: see scanNode in glb_loader.cpp.
              bones.back().entry.name = std::string(name.data(), name.size());
              if (!scanEntry(scan, bones.back(), dirs, scratch)) return false;
            } while (scan.consume(','));
            if (!scan.consume('}')) return false;
          } while (scan.consume(','));
          if (!scan.consume('}')) return false;
        }
      } else if (!scan.skipValue(scratch)) {
        return false;
      }
    } while (scan.consume(','));
    if (!scan.consume('}')) return false;
  }
  return seen_version && version == 1.0 && found && scan.atEnd();
}

// Entry indices in key order (nlohmann's objects are sorted maps: byte-wise, as std::string's <).
// False on a repeated name (nlohmann keeps the last; left to it). Names of one wearable share a
// long prefix ("springbone_"), so the sort orders by the 8 bytes after the common prefix as one
// integer, and by the whole names only where those tie: a memcmp per comparison was most of the
// cost of reading a 5,000-entry model.
struct SortKey {
  std::uint64_t key;  ///< bytes [prefix, prefix + 8) of the name, big-endian, zero-padded
  std::uint32_t index;
};

// Sorts keys by key, stably: least significant byte first, one counting pass per byte that is not
// the same in every key (often 3 or 4 of the 8). A comparison sort of 5,000 keys took three times
// as long in WebAssembly. `spare` is scratch.
void radixSortKeys(std::vector<SortKey>& keys, std::vector<SortKey>& spare) {
  const std::size_t count = keys.size();
  if (count < 2) return;
  std::uint64_t differ = 0;
  for (std::size_t i = 1; i < count; ++i) differ |= keys[i].key ^ keys[0].key;
  spare.resize(count);
  SortKey* from = keys.data();
  SortKey* to = spare.data();
  for (int shift = 0; shift < 64; shift += 8) {
    if (((differ >> shift) & 0xFF) == 0) continue;
    std::uint32_t start[256] = {};  // counts, then where each byte value's run starts
    for (std::size_t i = 0; i < count; ++i) ++start[(from[i].key >> shift) & 0xFF];
    std::uint32_t at = 0;
    for (std::uint32_t& s : start) {
      const std::uint32_t n = s;
      s = at;
      at += n;
    }
    for (std::size_t i = 0; i < count; ++i) to[start[(from[i].key >> shift) & 0xFF]++] = from[i];
    std::swap(from, to);
  }
  if (from != keys.data()) std::memcpy(keys.data(), from, count * sizeof(SortKey));
}

SPRINGBONES_NOINLINE bool sortNames(const std::vector<std::string_view>& names, std::vector<SortKey>& keys,
                                    std::vector<SortKey>& spare, std::vector<std::size_t>& order) {
  const std::size_t count = names.size();
  std::size_t prefix = count > 0 ? names[0].size() : 0;
  const char* first = count > 0 ? names[0].data() : nullptr;
  for (std::size_t i = 1; i < count && prefix > 0; ++i) {
    const char* name = names[i].data();
    const std::size_t limit = std::min(prefix, names[i].size());
    std::size_t k = 0;
    while (k < limit && first[k] == name[k]) ++k;
    prefix = k;
  }
  keys.clear();
  keys.reserve(count);  // filled by push_back: resize() would zero them first
  for (std::size_t i = 0; i < count; ++i) {
    const char* name = names[i].data();
    const std::size_t size = names[i].size();
    std::uint64_t key = 0;
    for (std::size_t k = 0; k < 8; ++k) {
      const std::size_t at = prefix + k;
      key = (key << 8) | (at < size ? static_cast<unsigned char>(name[at]) : 0u);
    }
    keys.push_back(SortKey{key, static_cast<std::uint32_t>(i)});
  }
  radixSortKeys(keys, spare);
  const auto less = [&](const SortKey& a, const SortKey& b) { return names[a.index] < names[b.index]; };
  // Runs of equal keys in name order.
  for (std::size_t i = 0; i < count;) {
    std::size_t end = i + 1;
    while (end < count && keys[end].key == keys[i].key) ++end;
    if (end - i > 1) std::sort(keys.begin() + i, keys.begin() + end, less);
    i = end;
  }
  for (std::size_t i = 0; i < count; ++i) order[i] = keys[i].index;
  for (std::size_t i = 1; i < count; ++i) {
    if (keys[i - 1].key == keys[i].key && names[order[i - 1]] == names[order[i]]) return false;
  }
  return true;
}

// An entry's param-missing warnings, in the order parseSpringBones reads the params: stiffness,
// gravityPower, gravityDir, drag.
SPRINGBONES_NOINLINE void warnMissing(const ModelEntry& model, const BoneEntry& bone, unsigned missing,
                                      std::vector<Warning>& warnings) {
  const std::string path = model.entryPath(bone);
  if (missing & kMissStiffness) {
    warnings.push_back(Warning{"param-missing", missingMessage(kStiffnessRange), path + "/stiffness"});
  }
  if (missing & kMissGravityPower) {
    warnings.push_back(Warning{"param-missing", missingMessage(kGravityPowerRange), path + "/gravityPower"});
  }
  if (missing & kMissGravityDir) {
    warnings.push_back(Warning{"param-missing", kGravityDirMissing, path + "/gravityDir"});
  }
  if (missing & kMissDrag) {
    warnings.push_back(Warning{"param-missing", missingMessage(kDragRange), path + "/drag"});
  }
}

// The entries in that order, with their param-missing warnings, as parseSpringBones would produce
// them. (No locals with destructors: see SPRINGBONES_NOINLINE.)
SPRINGBONES_NOINLINE void emitScanned(std::vector<ScannedBone>& bones, const std::vector<std::size_t>& order,
                                      ModelEntry& out, std::vector<Warning>& warnings) {
  out.enabled = true;
  out.bones.reserve(bones.size());
  for (std::size_t index : order) {
    ScannedBone& bone = bones[index];
    if (bone.missing != 0) warnMissing(out, bone.entry, bone.missing, warnings);
    out.bones.push_back(std::move(bone.entry));
  }
}

// Entries handed over already decoded (readSpringBonesEntries, whose comment in json_scan.h has
// the layout): the same acceptance as scanEntry, on values instead of text.
bool readEntry(const std::uint8_t* values, std::uint32_t flags, GravityDirs& dirs, BoneEntry& entry,
               unsigned& missing) {
  double v[6];
  std::memcpy(v, values, sizeof v);
  if ((flags & kEntryStiffness) && !acceptParam(v[0], kStiffnessRange, entry.params.stiffness)) return false;
  if ((flags & kEntryGravityPower) && !acceptParam(v[1], kGravityPowerRange, entry.params.gravity_power)) {
    return false;
  }
  if ((flags & kEntryDrag) && !acceptParam(v[2], kDragRange, entry.params.drag)) return false;
  if (flags & kEntryGravityDir) {
    double dir[3] = {v[3], v[4], v[5]};
    for (double c : dir) {
      if (!acceptGravityDirComponent(c)) return false;
    }
    if (!dirs.unit(dir, entry.params.gravity_dir)) return false;
  }
  entry.has_center = (flags & kEntryCenter) != 0;
  entry.is_root = (flags & kEntryIsRoot) != 0;
  missing = ((flags & kEntryStiffness) ? 0 : kMissStiffness) | ((flags & kEntryGravityPower) ? 0 : kMissGravityPower) |
            ((flags & kEntryGravityDir) ? 0 : kMissGravityDir) | ((flags & kEntryDrag) ? 0 : kMissDrag);
  return true;
}

// The sections of readSpringBonesEntries' layout, located and bounds-checked by entriesLayout.
struct EntriesLayout {
  std::size_t count = 0;
  const std::uint8_t* values = nullptr;       ///< 6 doubles per entry
  const std::uint8_t* name_ends = nullptr;    ///< u32 per entry
  const std::uint8_t* center_ends = nullptr;  ///< u32 per entry
  const std::uint8_t* flags = nullptr;        ///< u32 per entry
  const char* names = nullptr;
  const char* centers = nullptr;
  std::uint32_t name_bytes = 0, center_bytes = 0;
};

std::uint32_t u32At(const std::uint8_t* p, std::size_t index) {
  std::uint32_t v;
  std::memcpy(&v, p + 4 * index, sizeof v);
  return v;
}

// False unless `size` is exactly what the header announces. In 64 bits: the announced sizes are
// untrusted and would wrap around a 32-bit size_t (WebAssembly).
bool entriesLayout(const std::uint8_t* data, std::size_t size, EntriesLayout& out) {
  if (size < kEntriesHeaderBytes) return false;
  const std::uint32_t count = u32At(data, 0);
  out.name_bytes = u32At(data, 1);
  out.center_bytes = u32At(data, 2);
  if (u32At(data, 3) != 0 || count > kMaxMetadataBytes) return false;
  const std::uint64_t expected = std::uint64_t{kEntriesHeaderBytes} + std::uint64_t{kEntryBytes} * count +
                                 out.name_bytes + out.center_bytes;
  if (expected != size) return false;
  out.count = count;
  out.values = data + kEntriesHeaderBytes;
  out.name_ends = out.values + 48 * out.count;
  out.center_ends = out.name_ends + 4 * out.count;
  out.flags = out.center_ends + 4 * out.count;
  out.names = reinterpret_cast<const char*>(out.flags + 4 * out.count);
  out.centers = out.names + out.name_bytes;
  return true;
}

// Checks the ends and flags of the entries and gives each one's name (a view of the layout). Every
// end must follow the previous one and the last must close its section; a center's bytes only with
// kEntryCenterName, which needs kEntryCenter; names and centers well-formed UTF-8, as any string
// of the JSON text is (the JS writer never makes others: TextEncoder, lone surrogates declined).
// No locals with destructors (see SPRINGBONES_NOINLINE).
SPRINGBONES_NOINLINE bool checkEntries(const EntriesLayout& layout, std::vector<std::string_view>& names) {
  constexpr std::uint32_t kKnownFlags = kEntryStiffness | kEntryGravityPower | kEntryGravityDir | kEntryDrag |
                                        kEntryCenter | kEntryCenterName | kEntryIsRoot;
  std::uint32_t name_start = 0, center_start = 0;
  for (std::size_t i = 0; i < layout.count; ++i) {
    const std::uint32_t name_end = u32At(layout.name_ends, i), center_end = u32At(layout.center_ends, i);
    const std::uint32_t flags = u32At(layout.flags, i);
    if ((flags & ~kKnownFlags) != 0 || ((flags & kEntryCenterName) && !(flags & kEntryCenter))) return false;
    if (name_end < name_start || name_end > layout.name_bytes || center_end < center_start ||
        center_end > layout.center_bytes || (center_end != center_start && !(flags & kEntryCenterName))) {
      return false;
    }
    names[i] = std::string_view(layout.names + name_start, name_end - name_start);
    if (!wellFormedUtf8(names[i]) ||
        !wellFormedUtf8(std::string_view(layout.centers + center_start, center_end - center_start))) {
      return false;
    }
    name_start = name_end;
    center_start = center_end;
  }
  return name_start == layout.name_bytes && center_start == layout.center_bytes;
}

// The checked entries straight into `out` in key order (`order`), with their param-missing
// warnings; false for a value the fast readers do not take. Sorting views of the names first
// spares building every entry twice (a ScannedBone, then a move into `out`).
SPRINGBONES_NOINLINE bool emitEntries(const EntriesLayout& layout, const std::vector<std::string_view>& names,
                                      const std::vector<std::size_t>& order, ModelEntry& out,
                                      std::vector<Warning>& warnings) {
  out.enabled = true;
  out.bones.resize(layout.count);
  GravityDirs dirs;
  for (std::size_t k = 0; k < layout.count; ++k) {
    const std::size_t i = order[k];
    const std::uint32_t flags = u32At(layout.flags, i);
    BoneEntry& entry = out.bones[k];
    unsigned missing = 0;
    if (!readEntry(layout.values + 48 * i, flags, dirs, entry, missing)) return false;
    entry.name = std::string(names[i].data(), names[i].size());  // not assign(): see scanNode in glb_loader.cpp
    if (flags & kEntryCenterName) {
      const std::uint32_t start = i > 0 ? u32At(layout.center_ends, i - 1) : 0;
      entry.center = std::string(layout.centers + start, u32At(layout.center_ends, i) - start);
    }
    if (missing != 0) warnMissing(out, entry, missing, warnings);
  }
  return true;
}

bool finishScan(std::vector<ScannedBone>& bones, const std::string& hash, ModelEntry& out,
                std::vector<Warning>& warnings) {
  std::vector<std::string_view> names(bones.size());
  for (std::size_t i = 0; i < bones.size(); ++i) names[i] = bones[i].entry.name;
  std::vector<std::size_t> order(bones.size());
  std::vector<SortKey> keys, spare;
  if (!sortNames(names, keys, spare, order)) return false;
  out.path = "/models" + pointerToken(hash);
  emitScanned(bones, order, out, warnings);
  return true;
}

}  // namespace

Error parseSpringBones(const json& springBones, const std::string& hash, ModelEntry& out,
                       std::vector<Warning>& warnings) {
  out = ModelEntry{};
  if (springBones.is_null()) return {};
  if (!springBones.is_object()) {
    return Error{ErrorCode::kMetadataInvalid, "springBones is " + describe(springBones) +
                                                  ", not an object", ""};
  }
  EntryReader reader(warnings);
  auto version = springBones.find("version");
  if (version == springBones.end() || !version->is_number() || version->get<double>() != 1.0) {
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
    return Error{ErrorCode::kMetadataInvalid,
                 "springBones.models is " + describe(*models) + ", not an object", "/models"};
  }
  auto model = models->find(hash);
  if (model == models->end()) {
    std::string keys;
    for (auto it = models->begin(); it != models->end(); ++it) {
      keys += (keys.empty() ? "" : ", ") + it.key();
    }
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
                 "springBones.models[" + hash + "] is " + describe(*model) + ", not an object",
                 model_path};
  }
  out.enabled = true;
  out.path = model_path;
  out.bones.reserve(model->size());
  for (auto it = model->begin(); it != model->end(); ++it) {
    const std::string path = model_path + pointerToken(it.key());
    if (!it->is_object()) {
      reader.warn("bone-entry-invalid",
                  "entry for '" + it.key() + "' is " + describe(*it) + ", not an object; ignored",
                  path);
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

bool readSpringBonesEntries(const std::uint8_t* data, std::size_t size, const std::string& hash, ModelEntry& out,
                            std::vector<Warning>& warnings) {
  out = ModelEntry{};
  EntriesLayout layout;
  if (!entriesLayout(data, size, layout)) return false;
  std::vector<std::string_view> names(layout.count);
  std::vector<std::size_t> order(layout.count);
  std::vector<SortKey> keys, spare;
  if (!checkEntries(layout, names) || !sortNames(names, keys, spare, order)) return false;
  std::vector<Warning> entry_warnings;
  out.path = "/models" + pointerToken(hash);
  if (!emitEntries(layout, names, order, out, entry_warnings)) {
    out = ModelEntry{};
    return false;
  }
  warnings.insert(warnings.end(), std::make_move_iterator(entry_warnings.begin()),
                  std::make_move_iterator(entry_warnings.end()));
  return true;
}

namespace {

Error parseSpringBonesTextWith(std::string_view text, const std::string& hash, ModelEntry& out,
                               std::vector<Warning>& warnings, bool fast) {
  out = ModelEntry{};
  if (text.size() > kMaxMetadataBytes) {
    return Error{ErrorCode::kLimitExceeded,
                 "springBones JSON is " + std::to_string(text.size()) +
                     " bytes, more than the limit of " + std::to_string(kMaxMetadataBytes),
                 ""};
  }
  {
    std::vector<ScannedBone> bones;
    std::string scratch;
    if (fast && scanSpringBones(text, hash, bones, scratch)) {
      std::vector<Warning> fast_warnings;
      if (finishScan(bones, hash, out, fast_warnings)) {
        warnings.insert(warnings.end(), std::make_move_iterator(fast_warnings.begin()),
                        std::make_move_iterator(fast_warnings.end()));
        return {};
      }
      out = ModelEntry{};
    }
  }
  json value;
  try {
    value = json::parse(text.data(), text.data() + text.size());
  } catch (const json::exception& ex) {
    return Error{ErrorCode::kMetadataBadJson,
                 std::string("springBones JSON does not parse: ") + ex.what(), ""};
  }
  return parseSpringBones(value, hash, out, warnings);
}

}  // namespace

Error parseSpringBonesText(const std::string& text, const std::string& hash, ModelEntry& out,
                           std::vector<Warning>& warnings) {
  return parseSpringBonesTextWith(text, hash, out, warnings, /*fast=*/true);
}

Error parseSpringBonesTextView(std::string_view text, const std::string& hash, ModelEntry& out,
                               std::vector<Warning>& warnings) {
  return parseSpringBonesTextWith(text, hash, out, warnings, /*fast=*/true);
}

Error parseSpringBonesTextChecked(const std::string& text, const std::string& hash, ModelEntry& out,
                                  std::vector<Warning>& warnings) {
  return parseSpringBonesTextWith(text, hash, out, warnings, /*fast=*/false);
}

bool fastSpringBonesReaderAccepts(const std::string& text, const std::string& hash) {
  std::vector<ScannedBone> bones;
  std::string scratch;
  ModelEntry model;
  std::vector<Warning> warnings;
  return text.size() <= kMaxMetadataBytes && scanSpringBones(text, hash, bones, scratch) &&
         finishScan(bones, hash, model, warnings);
}

}  // namespace springbones
