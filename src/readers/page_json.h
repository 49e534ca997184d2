// glTF JSON text read as a page reads it: TextDecoder (UTF-8, each ill-formed sequence replaced by
// U+FFFD, a leading byte order mark dropped), then JSON.parse (ECMA-404's grammar, numbers rounded
// to the nearest double with -0 kept and overflow as an infinity, escapes of lone surrogates
// allowed, nothing but whitespace after the value). Of the document it keeps only the members the
// runtime reads (src/common/typed_encoding.json, "gltf"); every other member is checked for JSON
// syntax alone, as JSON.parse checks it, and never copied or validated (docs/input.md).
#pragma once

#include <cstddef>

#include <nlohmann/json.hpp>

#include "springbones/springbones.h"

namespace springbones {

/// The kept members of the glTF JSON `text` (`extensions` only when `with_extensions`) into
/// `out`: asset.version, each node's fields, the root extensions the runtime reads. A kept member
/// in a place that must be an object or array and is not keeps its kind only (a string there is
/// written empty). Errors: kGltfBadJson (what JSON.parse refuses), kGltfInvalid (a kept string
/// with a lone surrogate, which the page cannot hand over either), kLimitExceeded (more nodes than
/// kMaxNodes, or a kept value past a bound of the typed input), each with the JSON path.
Error readGltfJsonAsPage(const char* text, std::size_t size, bool with_extensions, nlohmann::json& out);

}  // namespace springbones
