#include "loading/entity.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "common/name_index.h"
#include "common/shown_name.h"

namespace springbones {
namespace {

TypedValue field(const TypedValue& object, const char* key) {
  auto it = object.find(key);
  return it == object.end() ? TypedValue() : *it;
}

// The item data: entity.metadata.data for a catalyst entity, item.data for a Builder item.
TypedValue dataOf(const TypedValue& entity) {
  const TypedValue from_metadata = field(field(entity, "metadata"), "data");
  return from_metadata.is_object() ? from_metadata : field(entity, "data");
}

Error invalid(std::string message, std::string path) {
  return Error{ErrorCode::kInvalidArgument, std::move(message), std::move(path)};
}

bool bodyShapeMatches(const std::string& listed, const std::string& wanted) {
  if (listed == wanted) return true;
  const std::size_t colon = listed.rfind(':');
  return colon != std::string::npos && listed.compare(colon + 1, std::string::npos, wanted) == 0;
}

// The last segment of a body shape URN ("BaseMale" of "urn:decentraland:off-chain:base-avatars:BaseMale").
std::string lastSegment(const std::string& shape) {
  const std::size_t colon = shape.rfind(':');
  return colon == std::string::npos ? shape : shape.substr(colon + 1);
}

bool equalsIgnoringAsciiCase(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; };
    if (lower(a[i]) != lower(b[i])) return false;
  }
  return true;
}

// No representation lists `wanted`: the message lists the body shapes the entity has (at most
// kListed, a name quoted at most kQuoted bytes), and the one `wanted` differs from only by case
// (matching is case-sensitive, as the catalyst writes the URNs).
std::string noRepresentationMessage(const std::vector<Representation>& representations, const std::string& wanted) {
  constexpr std::size_t kListed = 8;
  const auto quoted = [](const std::string& s) { return "'" + shownName(s) + "'"; };
  std::vector<std::string> shapes;
  for (const Representation& r : representations) {
    for (const std::string& shape : r.body_shapes) {
      if (std::find(shapes.begin(), shapes.end(), shape) == shapes.end()) shapes.push_back(shape);
    }
  }
  std::string message = "the entity has no representation for body shape " + quoted(wanted);
  if (shapes.empty()) return message + ": its representations list no body shapes";
  message += "; its body shapes are ";
  for (std::size_t i = 0; i < shapes.size() && i < kListed; ++i) message += (i > 0 ? ", " : "") + quoted(shapes[i]);
  if (shapes.size() > kListed) message += " and " + std::to_string(shapes.size() - kListed) + " more";
  message += " (give one, or its last segment, with the same case)";
  for (const std::string& shape : shapes) {
    if (equalsIgnoringAsciiCase(lastSegment(shape), wanted) || equalsIgnoringAsciiCase(shape, wanted)) {
      return message + "; did you mean " + quoted(equalsIgnoringAsciiCase(shape, wanted) ? shape : lastSegment(shape)) +
             "?";
    }
  }
  return message;
}

}  // namespace

Error readRepresentations(const TypedValue& entity, std::vector<Representation>& out) {
  out.clear();
  if (!entity.is_object()) return invalid("the entity is not an object", "");
  // Content hashes by file name: an array of {file, hash} (catalyst entity) or an object
  // {file: hash} (Builder item `contents`).
  // The first entry of a file wins; looked up by name, so many representations over a long content
  // list stay linear.
  // {file, hash} in the list's order, reserved whole so that the index's views of the names stay put.
  std::vector<std::pair<std::string, std::string>> files;
  const TypedValue content = field(entity, "content");
  const TypedValue contents = field(entity, "contents");
  if (content.is_array()) {
    files.reserve(content.size());
    for (std::size_t i = 0; i < content.size(); ++i) {
      const TypedValue f = field(content[i], "file");
      const TypedValue h = field(content[i], "hash");
      if (!f.is_string() || !h.is_string()) {
        return invalid("content entry is not {file, hash} strings", "/content/" + std::to_string(i));
      }
      files.emplace_back(f.get<std::string>(), h.get<std::string>());
    }
  } else if (contents.is_object()) {
    files.reserve(contents.size());
    for (auto it = contents.begin(); it != contents.end(); ++it) {
      if (!it->is_string()) return invalid("contents value is not a hash string", "/contents/" + it.key());
      files.emplace_back(it.key(), it->get<std::string>());
    }
  } else if (!content.is_null() || !contents.is_null()) {
    return invalid("the entity's content list is neither an array nor an object", "/content");
  }
  NameIndex file_index;
  file_index.reserve(files.size());
  for (std::size_t i = 0; i < files.size(); ++i) file_index.insertFirst(files[i].first, static_cast<int>(i));

  const TypedValue representations = field(dataOf(entity), "representations");
  if (!representations.is_array()) {
    return invalid("the entity has no data.representations array", "/metadata/data/representations");
  }
  for (std::size_t i = 0; i < representations.size(); ++i) {
    const std::string path = "/metadata/data/representations/" + std::to_string(i);
    const TypedValue r = representations[i];
    const TypedValue main_file = field(r, "mainFile");
    if (!main_file.is_string()) return invalid("representation has no mainFile string", path + "/mainFile");
    Representation rep;
    rep.main_file = main_file.get<std::string>();
    const TypedValue shapes = field(r, "bodyShapes");
    if (shapes.is_array()) {
      for (const TypedValue& s : shapes) {
        if (s.is_string()) rep.body_shapes.push_back(s.get<std::string>());
      }
    }
    if (const int file = file_index.find(rep.main_file); file >= 0) rep.main_file_hash = files[file].second;
    out.push_back(std::move(rep));
  }
  return {};
}

Error mainFileHashFor(const TypedValue& entity, const std::string& body_shape, std::string& hash) {
  hash.clear();
  std::vector<Representation> representations;
  if (Error e = readRepresentations(entity, representations)) return e;
  for (const Representation& r : representations) {
    for (const std::string& shape : r.body_shapes) {
      if (!bodyShapeMatches(shape, body_shape)) continue;
      if (r.main_file_hash.empty()) {
        return invalid("main file '" + shownName(r.main_file) + "' of body shape " + shownName(body_shape) +
                           " is not in the entity's content list",
                       "/content");
      }
      hash = r.main_file_hash;
      return {};
    }
  }
  return invalid(noRepresentationMessage(representations, body_shape), "/metadata/data/representations");
}

}  // namespace springbones
