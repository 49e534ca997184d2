// Decentraland content hash: the CIDv1 that `hashV1` of npm @dcl/hashing (3.x) gives a file,
// i.e. what the catalyst and the Builder use as the key of a wearable's GLB or texture.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace springbones {

// Returns the content hash of the size bytes at data as a CIDv1 string ("bafkrei..." or "bafybei...").
// Accepts any size, including 0 (data may be null only when size is 0); reads data in place.
// Throws nothing for any input (only std::bad_alloc if a few kilobytes cannot be allocated).
std::string contentHash(const std::uint8_t* data, std::size_t size);

}  // namespace springbones
