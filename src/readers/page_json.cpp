// One pass over the text with an explicit stack (no recursion at any depth). Each open container
// carries the rule of what to keep inside it; a skipped value is scanned for its syntax only.
#include "readers/page_json.h"

#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/shown_name.h"
#include "common/typed_encoding.h"
#include "common/utf8_append.h"

namespace springbones {
namespace {

using nlohmann::json;

// What to keep of a value: nothing (syntax only), all of it, or some of its members or every
// element by a rule of their own (a value of another kind there keeps its kind only).
struct Rule {
  enum Kind : std::uint8_t { kSkip, kAll, kMembers, kElements };
  explicit Rule(Kind k) : kind(k) {}
  Kind kind;
  std::vector<std::pair<std::string, const Rule*>> members;  ///< kMembers
  const Rule* element = nullptr;                             ///< kElements
  std::size_t max_elements = kTypedMaxContainerSize;
  const Rule* member(std::string_view key) const {
    for (const auto& [name, rule] : members) {
      if (name == key) return rule;
    }
    return nullptr;
  }
};

// The rules of typed_encoding.json's "gltf", built once from typed_encoding.h.
struct GltfRules {
  Rule all{Rule::kAll};
  Rule skip{Rule::kSkip};
  Rule asset{Rule::kMembers};
  Rule node{Rule::kMembers};
  Rule nodes{Rule::kElements};
  Rule extensions{Rule::kMembers};
  std::vector<Rule> extension_rules;
  Rule root_with_extensions{Rule::kMembers};
  Rule root{Rule::kMembers};

  GltfRules() {
    asset.members = {{"version", &all}};
    for (const char* field : kGltfNodeFields) node.members.emplace_back(field, &all);
    nodes.element = &node;
    nodes.max_elements = kMaxNodes;
    extension_rules.reserve(std::size(kGltfRootExtensionMembers));
    for (const auto& [extension, member] : kGltfRootExtensionMembers) {
      if (const Rule* known = extensions.member(extension)) {
        const_cast<Rule*>(known)->members.emplace_back(member, &all);
        continue;
      }
      extension_rules.push_back(member == nullptr ? Rule{Rule::kAll} : Rule{Rule::kMembers});
      if (member != nullptr) extension_rules.back().members.emplace_back(member, &all);
      extensions.members.emplace_back(extension, &extension_rules.back());
    }
    root.members = {{"asset", &asset}, {"nodes", &nodes}};
    root_with_extensions.members = {{"asset", &asset}, {"nodes", &nodes}, {"extensions", &extensions}};
  }
};

const GltfRules& gltfRules() {
  static const GltfRules rules;
  return rules;
}

constexpr std::uint32_t kReplacement = 0xFFFD;

class PageParser {
 public:
  PageParser(const char* text, std::size_t size) : p_(reinterpret_cast<const unsigned char*>(text)), size_(size) {}

  Error parse(const Rule& root_rule, json& out);

 private:
  struct Frame {
    json* value;       ///< the kept container
    const Rule* rule;  ///< what to keep of its children
    bool object;
    std::size_t count;  ///< children so far
    std::string key;    ///< objects: the current member's key (kept containers only)
  };

  Error syntax(const std::string& what) const {
    return Error{ErrorCode::kGltfBadJson,
                 "glTF JSON does not parse: " + what + " at byte " + std::to_string(at_) + " (JSON.parse refuses it)",
                 ""};
  }
  std::string path() const;
  void whitespace() {
    while (at_ < size_ && (p_[at_] == ' ' || p_[at_] == '\t' || p_[at_] == '\n' || p_[at_] == '\r')) ++at_;
  }
  Error string(std::string* out, bool& lone_surrogate);
  Error number(double& out);
  Error literal(const char* word);
  Error value(const Rule* rule, json* slot);

  const unsigned char* p_;
  std::size_t size_;
  std::size_t at_ = 0;
  std::size_t values_ = 0;
  std::vector<Frame> open_;  ///< kept containers, outermost first
  // Skipped containers, nested inside the innermost kept one (or at the top).
  static constexpr std::uint8_t kSkippedObject = 1;
  static constexpr std::uint8_t kSkippedNotEmpty = 2;
  std::vector<std::uint8_t> skipped_;
};

std::string PageParser::path() const {
  std::string out;
  for (const Frame& f : open_) {
    out += "/" + (f.object ? shownName(f.key) : std::to_string(f.count == 0 ? 0 : f.count - 1));
  }
  return out;
}

// A string after its opening quote. Kept (`out` not null): decoded as TextDecoder decodes the
// bytes and JSON.parse the escapes; a lone surrogate is reported, since UTF-8 cannot hold it.
Error PageParser::string(std::string* out, bool& lone_surrogate) {
  lone_surrogate = false;
  std::uint32_t cp = 0;
  int needed = 0;
  int seen = 0;
  unsigned char lower = 0x80;
  unsigned char upper = 0xBF;
  std::uint32_t pending_high = 0;  // an escaped high surrogate waiting for its low half
  const auto flushHigh = [&] {
    if (pending_high != 0) {
      lone_surrogate = true;
      pending_high = 0;
    }
  };
  for (;;) {
    if (at_ >= size_) return syntax("an unterminated string");
    const unsigned char b = p_[at_];
    if (needed > 0) {
      if (b >= lower && b <= upper) {
        lower = 0x80;
        upper = 0xBF;
        cp = (cp << 6) | (b & 0x3F);
        ++at_;
        if (++seen == needed) {
          if (out != nullptr) appendUtf8(*out, cp);
          needed = 0;
        }
        continue;
      }
      // An ill-formed sequence: one U+FFFD, and this byte read afresh.
      needed = 0;
      lower = 0x80;
      upper = 0xBF;
      if (out != nullptr) appendUtf8(*out, kReplacement);
      continue;
    }
    if (b == '"') {
      flushHigh();
      ++at_;
      return {};
    }
    if (b < 0x20) return syntax("a control character in a string");
    if (b == '\\') {
      if (at_ + 1 >= size_) return syntax("an unterminated string");
      const unsigned char e = p_[at_ + 1];
      at_ += 2;
      std::uint32_t unit = 0;
      switch (e) {
        case '"': unit = '"'; break;
        case '\\': unit = '\\'; break;
        case '/': unit = '/'; break;
        case 'b': unit = '\b'; break;
        case 'f': unit = '\f'; break;
        case 'n': unit = '\n'; break;
        case 'r': unit = '\r'; break;
        case 't': unit = '\t'; break;
        case 'u': {
          if (size_ - at_ < 4) return syntax("a short \\u escape");
          for (int i = 0; i < 4; ++i) {
            const unsigned char h = p_[at_ + i];
            const int digit = h >= '0' && h <= '9'   ? h - '0'
                              : h >= 'a' && h <= 'f' ? h - 'a' + 10
                              : h >= 'A' && h <= 'F' ? h - 'A' + 10
                                                     : -1;
            if (digit < 0) return syntax("a \\u escape that is not four hex digits");
            unit = (unit << 4) | static_cast<std::uint32_t>(digit);
          }
          at_ += 4;
          break;
        }
        default: --at_; return syntax("an unknown escape");
      }
      if (unit >= 0xDC00 && unit <= 0xDFFF && pending_high != 0) {
        if (out != nullptr) appendUtf8(*out, 0x10000 + ((pending_high - 0xD800) << 10) + (unit - 0xDC00));
        pending_high = 0;
        continue;
      }
      flushHigh();
      if (unit >= 0xD800 && unit <= 0xDBFF) {
        pending_high = unit;
      } else if (unit >= 0xDC00 && unit <= 0xDFFF) {
        lone_surrogate = true;
      } else if (out != nullptr) {
        appendUtf8(*out, unit);
      }
      continue;
    }
    flushHigh();
    ++at_;
    if (b < 0x80) {
      if (out != nullptr) *out += static_cast<char>(b);
    } else if (b >= 0xC2 && b <= 0xDF) {
      needed = 1, seen = 0, cp = b & 0x1F;
    } else if (b >= 0xE0 && b <= 0xEF) {
      needed = 2, seen = 0, cp = b & 0x0F;
      if (b == 0xE0) lower = 0xA0;
      if (b == 0xED) upper = 0x9F;
    } else if (b >= 0xF0 && b <= 0xF4) {
      needed = 3, seen = 0, cp = b & 0x07;
      if (b == 0xF0) lower = 0x90;
      if (b == 0xF4) upper = 0x8F;
    } else if (out != nullptr) {
      appendUtf8(*out, kReplacement);
    }
  }
}

// A number by JSON's grammar, valued by strtod: the nearest double, as JSON.parse rounds, -0 kept,
// beyond the double range an infinity.
Error PageParser::number(double& out) {
  const std::size_t start = at_;
  const auto digits = [&] {
    const std::size_t from = at_;
    while (at_ < size_ && p_[at_] >= '0' && p_[at_] <= '9') ++at_;
    return at_ > from;
  };
  if (at_ < size_ && p_[at_] == '-') ++at_;
  if (at_ < size_ && p_[at_] == '0') {
    ++at_;
  } else if (!digits()) {
    return syntax("a number without digits");
  }
  if (at_ < size_ && p_[at_] == '.') {
    ++at_;
    if (!digits()) return syntax("a number without digits after its point");
  }
  if (at_ < size_ && (p_[at_] == 'e' || p_[at_] == 'E')) {
    ++at_;
    if (at_ < size_ && (p_[at_] == '+' || p_[at_] == '-')) ++at_;
    if (!digits()) return syntax("a number without digits in its exponent");
  }
  const std::string token(reinterpret_cast<const char*>(p_ + start), at_ - start);
  out = std::strtod(token.c_str(), nullptr);
  return {};
}

Error PageParser::literal(const char* word) {
  const std::string_view w(word);
  if (size_ - at_ < w.size() || std::string_view(reinterpret_cast<const char*>(p_ + at_), w.size()) != w) {
    return syntax("an unexpected character");
  }
  at_ += w.size();
  return {};
}

// One value at at_ under `rule`; `slot` is where a kept value goes (null when skipped).
Error PageParser::value(const Rule* rule, json* slot) {
  whitespace();
  if (at_ >= size_) return syntax("a missing value");
  const bool keep = slot != nullptr && rule->kind != Rule::kSkip;
  if (keep && ++values_ > kTypedMaxValues) {
    return Error{ErrorCode::kLimitExceeded,
                 "glTF JSON: the members the runtime reads hold more than the limit of " +
                     std::to_string(kTypedMaxValues) + " values",
                 path()};
  }
  const unsigned char c = p_[at_];
  if (c == '{' || c == '[') {
    ++at_;
    const bool object = c == '{';
    if (keep) {
      // A container where the rule expects the other kind is kept empty: the runtime reads its
      // type, never what is in it.
      const bool as_rule = rule->kind == Rule::kAll || (object && rule->kind == Rule::kMembers) ||
                           (!object && rule->kind == Rule::kElements);
      *slot = object ? json::object() : json::array();
      if (as_rule) {
        open_.push_back(Frame{slot, rule, object, 0, {}});
        return {};
      }
    }
    // Skipped: one byte of stack per level, however deep the unread member nests.
    skipped_.push_back(object ? kSkippedObject : 0);
    return {};
  }
  if (c == '"') {
    ++at_;
    const bool whole = keep && rule->kind == Rule::kAll;
    std::string text;
    bool lone = false;
    if (Error e = string(whole ? &text : nullptr, lone)) return e;
    if (!keep) return {};
    if (!whole) {
      *slot = "";  // its kind only
      return {};
    }
    if (lone) {
      return Error{ErrorCode::kGltfInvalid,
                   "glTF JSON: the string at " + path() +
                       " contains a lone surrogate (half of a UTF-16 pair), which UTF-8 cannot encode",
                   path()};
    }
    if (text.size() > kTypedMaxStringBytes) {
      return Error{ErrorCode::kLimitExceeded,
                   "glTF JSON: a string of " + std::to_string(text.size()) + " bytes, more than the limit of " +
                       std::to_string(kTypedMaxStringBytes),
                   path()};
    }
    *slot = std::move(text);
    return {};
  }
  if (c == 't' || c == 'f' || c == 'n') {
    if (Error e = literal(c == 't' ? "true" : c == 'f' ? "false" : "null")) return e;
    if (keep) *slot = c == 't' ? json(true) : c == 'f' ? json(false) : json(nullptr);
    return {};
  }
  if (c == '-' || (c >= '0' && c <= '9')) {
    double v = 0;
    if (Error e = number(v)) return e;
    if (keep) *slot = v;
    return {};
  }
  return syntax("an unexpected character");
}

Error PageParser::parse(const Rule& root_rule, json& out) {
  // TextDecoder drops one leading byte order mark.
  if (size_ >= 3 && p_[0] == 0xEF && p_[1] == 0xBB && p_[2] == 0xBF) at_ = 3;
  out = nullptr;
  if (Error e = value(&root_rule, &out)) return e;
  while (!open_.empty() || !skipped_.empty()) {
    whitespace();
    if (at_ >= size_) return syntax("an unterminated array or object");
    if (!skipped_.empty()) {
      std::uint8_t& top = skipped_.back();
      const bool object = (top & kSkippedObject) != 0;
      if (p_[at_] == (object ? '}' : ']')) {
        ++at_;
        skipped_.pop_back();
        continue;
      }
      if ((top & kSkippedNotEmpty) != 0) {
        if (p_[at_] != ',') return syntax("a missing comma");
        ++at_;
        whitespace();
      }
      top |= kSkippedNotEmpty;
      if (object) {
        if (at_ >= size_ || p_[at_] != '"') return syntax("a member without a string key");
        ++at_;
        bool lone = false;
        if (Error e = string(nullptr, lone)) return e;
        whitespace();
        if (at_ >= size_ || p_[at_] != ':') return syntax("a member without a colon");
        ++at_;
      }
      if (Error e = value(&gltfRules().skip, nullptr)) return e;
      continue;
    }
    Frame& f = open_.back();
    if (p_[at_] == (f.object ? '}' : ']')) {
      ++at_;
      open_.pop_back();
      continue;
    }
    if (f.count > 0) {
      if (p_[at_] != ',') return syntax("a missing comma");
      ++at_;
      whitespace();
    }
    const std::size_t max = f.rule->kind == Rule::kElements ? f.rule->max_elements : kTypedMaxContainerSize;
    if (f.count == max) {
      std::string where = path();
      where.erase(where.rfind('/'));  // the container's own path
      return Error{ErrorCode::kLimitExceeded,
                   max == kMaxNodes && f.rule->kind == Rule::kElements
                       ? "glTF has more nodes than the limit of " + std::to_string(kMaxNodes)
                       : "glTF JSON: more than the limit of " + std::to_string(max) + " elements or members",
                   where};
    }
    ++f.count;
    const Rule* child_rule = nullptr;
    json* slot = nullptr;
    if (f.object) {
      if (at_ >= size_ || p_[at_] != '"') return syntax("a member without a string key");
      ++at_;
      std::string key;
      bool lone = false;
      if (Error e = string(&key, lone)) return e;
      whitespace();
      if (at_ >= size_ || p_[at_] != ':') return syntax("a member without a colon");
      ++at_;
      // In an object kept whole, every key is kept; in one kept by its members, a key with a lone
      // surrogate names none of them.
      child_rule = f.rule->kind == Rule::kAll ? f.rule : (lone ? nullptr : f.rule->member(key));
      f.key = std::move(key);
      if (child_rule != nullptr) {
        if (lone) {
          return Error{ErrorCode::kGltfInvalid,
                       "glTF JSON: a key at " + path() +
                           " contains a lone surrogate (half of a UTF-16 pair), which UTF-8 cannot encode",
                       path()};
        }
        if (f.key.size() > kTypedMaxStringBytes) {
          return Error{ErrorCode::kLimitExceeded,
                       "glTF JSON: a key of " + std::to_string(f.key.size()) + " bytes, more than the limit of " +
                           std::to_string(kTypedMaxStringBytes),
                       path()};
        }
        // JSON.parse keeps the last of repeated keys: assigning replaces.
        slot = &(*f.value)[f.key];
        *slot = nullptr;
      }
    } else {
      child_rule = f.rule->kind == Rule::kAll ? f.rule : f.rule->element;
      f.value->push_back(nullptr);
      slot = &f.value->back();
    }
    // `f` may move when value() opens a container: nothing of it is used after this call.
    if (Error e =
            value(child_rule != nullptr ? child_rule : &gltfRules().skip, child_rule != nullptr ? slot : nullptr)) {
      return e;
    }
  }
  whitespace();
  if (at_ != size_) return syntax("something after the document");
  return {};
}

}  // namespace

Error readGltfJsonAsPage(const char* text, std::size_t size, bool with_extensions, json& out) {
  PageParser parser(text, size);
  const GltfRules& rules = gltfRules();
  return parser.parse(with_extensions ? rules.root_with_extensions : rules.root, out);
}

}  // namespace springbones
