#include "readers/json_values.h"

#include <utility>

#include "common/typed_value.h"
#include "loading/metadata.h"

namespace springbones {
namespace {

using nlohmann::json;

// `value` decoded, for the duration of `read`.
template <typename Read>
Error withTyped(const json& value, Read read) {
  std::vector<std::uint8_t> bytes;
  writeTyped(value, bytes);
  TypedDocument doc;
  if (Error e = doc.decode(bytes.data(), bytes.size(), kMaxMetadataBytes)) return e;
  return read(doc.root());
}

const json& member(const json& object, const char* key) {
  static const json kNull;
  if (!object.is_object()) return kNull;
  auto it = object.find(key);
  return it == object.end() ? kNull : *it;
}

}  // namespace

void writeTyped(const json& value, std::vector<std::uint8_t>& out) {
  TypedWriter writer;
  writer.bytes().swap(out);
  struct Frame {
    const json* container;
    json::const_iterator next;
  };
  std::vector<Frame> open;
  const auto write = [&](const json& v) {
    switch (v.type()) {
      case json::value_t::boolean: writer.boolean(v.get<bool>()); break;
      case json::value_t::number_integer:
      case json::value_t::number_unsigned:
      case json::value_t::number_float: writer.number(v.get<double>()); break;
      case json::value_t::string: writer.string(v.get_ref<const std::string&>()); break;
      case json::value_t::array:
        writer.array(static_cast<std::uint32_t>(v.size()));
        open.push_back(Frame{&v, v.cbegin()});
        break;
      case json::value_t::object:
        writer.object(static_cast<std::uint32_t>(v.size()));
        open.push_back(Frame{&v, v.cbegin()});
        break;
      default: writer.null(); break;
    }
  };
  write(value);
  while (!open.empty()) {
    Frame& top = open.back();
    if (top.next == top.container->cend()) {
      open.pop_back();
      continue;
    }
    if (top.container->is_object()) writer.key(top.next.key());
    const json& child = *top.next;
    ++top.next;
    write(child);  // may grow `open`: `top` is not used after this
  }
  writer.bytes().swap(out);
}

Error parseSpringBones(const json& springBones, const std::string& hash, ModelEntry& out,
                       std::vector<Warning>& warnings) {
  out = ModelEntry{};
  return withTyped(springBones, [&](const TypedValue& v) { return parseSpringBones(v, hash, out, warnings); });
}

Error readRepresentations(const json& entity, std::vector<Representation>& out) {
  out.clear();
  return withTyped(entity, [&](const TypedValue& v) { return readRepresentations(v, out); });
}

Error mainFileHashFor(const json& entity, const std::string& body_shape, std::string& hash) {
  hash.clear();
  return withTyped(entity, [&](const TypedValue& v) { return mainFileHashFor(v, body_shape, hash); });
}

const json& springBonesOf(const json& entity) {
  // The item data where the runtime's readRepresentations finds it (loading/entity.cpp):
  // metadata.data when it is an object, else data.
  const json& from_metadata = member(member(entity, "metadata"), "data");
  return member(from_metadata.is_object() ? from_metadata : member(entity, "data"), "springBones");
}

}  // namespace springbones
