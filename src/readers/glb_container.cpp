// The glTF JSON inside a GLB or a glTF text input (see glb_container.h): our own check of the
// container, so that each kind of bad container gets its error code.
#include "readers/glb_container.h"

#include <string>
#include <utility>

namespace springbones {
namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67;   // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::size_t kGlbHeaderBytes = 12;
constexpr std::size_t kChunkHeaderBytes = 8;

std::uint32_t readU32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) | (std::uint32_t(p[3]) << 24);
}

Error fail(ErrorCode code, std::string message) { return Error{code, std::move(message), {}}; }

bool looksLikeJsonText(const std::uint8_t* data, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) {
    const char c = static_cast<char>(data[i]);
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') continue;
    if (i == 0 && size >= 3 && data[0] == 0xEF && data[1] == 0xBB && data[2] == 0xBF) {
      i += 2;  // UTF-8 byte order mark
      continue;
    }
    return c == '{';
  }
  return false;
}

Error locate(const std::uint8_t* data, std::size_t size, const char*& json_begin, std::size_t& json_size) {
  if (size >= 4 && readU32(data) == kGlbMagic) {
    if (size < kGlbHeaderBytes + kChunkHeaderBytes) {
      return fail(ErrorCode::kGlbTruncated,
                  "GLB is " + std::to_string(size) + " bytes, shorter than its 20-byte header");
    }
    const std::uint32_t version = readU32(data + 4);
    if (version != 2) {
      return fail(ErrorCode::kGlbBadChunk,
                  "GLB container version " + std::to_string(version) + " is not supported (2 is)");
    }
    const std::uint32_t declared = readU32(data + 8);
    if (declared > size) {
      return fail(ErrorCode::kGlbTruncated, "GLB header declares " + std::to_string(declared) + " bytes but only " +
                                                std::to_string(size) + " are present");
    }
    if (declared < kGlbHeaderBytes + kChunkHeaderBytes) {
      return fail(ErrorCode::kGlbBadChunk, "GLB header declares a length of " + std::to_string(declared) + " bytes");
    }
    const std::uint32_t chunk_length = readU32(data + 12);
    const std::uint32_t chunk_type = readU32(data + 16);
    if (chunk_type != kChunkJson) return fail(ErrorCode::kGlbBadChunk, "the first GLB chunk is not a JSON chunk");
    if (std::size_t(chunk_length) > declared - kGlbHeaderBytes - kChunkHeaderBytes) {
      return fail(ErrorCode::kGlbTruncated,
                  "GLB JSON chunk declares " + std::to_string(chunk_length) + " bytes, more than the file holds");
    }
    json_begin = reinterpret_cast<const char*>(data + kGlbHeaderBytes + kChunkHeaderBytes);
    json_size = chunk_length;
    return {};
  }
  if (looksLikeJsonText(data, size)) {
    json_begin = reinterpret_cast<const char*>(data);
    json_size = size;
    return {};
  }
  if (size < 4) {
    return fail(ErrorCode::kGlbTruncated, "input is " + std::to_string(size) + " bytes: too short to be a GLB or glTF");
  }
  return fail(ErrorCode::kGlbBadMagic, "input is neither a GLB (magic 'glTF') nor glTF JSON text");
}

}  // namespace

Error findGltfJson(const std::uint8_t* data, std::size_t size, const char*& json_begin, std::size_t& json_size) {
  json_begin = nullptr;
  json_size = 0;
  if (data == nullptr && size != 0) return fail(ErrorCode::kInvalidArgument, "null GLB buffer");
  if (size == 0) return fail(ErrorCode::kGlbTruncated, "input is empty");
  const char* begin = nullptr;
  std::size_t length = 0;
  if (Error e = locate(data, size, begin, length)) return e;
  if (length > kMaxGltfJsonBytes) {
    return fail(ErrorCode::kLimitExceeded, "glTF JSON is " + std::to_string(length) +
                                               " bytes, more than the limit of " + std::to_string(kMaxGltfJsonBytes));
  }
  json_begin = begin;
  json_size = length;
  return {};
}

}  // namespace springbones
