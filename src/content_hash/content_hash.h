// Decentraland content hash: the CIDv1 that `hashV1` of npm @dcl/hashing (3.x) gives a file,
// i.e. what the catalyst and the Builder use as the key of a wearable's GLB or texture.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace springbones {

// Returns the content hash of the size bytes at data as a CIDv1 string ("bafkrei..." or "bafybei...").
// Accepts any size, including 0 (data may be null only when size is 0); reads data in place.
// Throws nothing for any input (only std::bad_alloc if a few kilobytes cannot be allocated).
std::string contentHash(const std::uint8_t* data, std::size_t size);

// The pieces of contentHash, exposed so tests can check intermediate bytes against the worked
// example of docs/content-hash.md and exercise deep trees with small chunks. Not part of the
// stable API.
namespace detail {

using Cid = std::array<std::uint8_t, 36>;  // 0x01 codec 0x12 0x20 + sha256: CIDv1, sha2-256

// A node of the file DAG as its parent sees it (one PBLink plus one UnixFS blocksize).
struct FileLink {
  Cid cid;                    ///< CID bytes of the child block
  std::uint64_t tsize;        ///< bytes of every block in the child's subtree (PBLink Tsize)
  std::uint64_t file_size;    ///< file bytes the child covers (UnixFS blocksize)
};

// The CID of a chunk stored as a raw block (codec 0x55).
Cid rawLeafCid(const std::uint8_t* chunk, std::size_t size);

// The dag-pb block of a UnixFS file node with these children, in order.
std::vector<std::uint8_t> encodeFileNode(const FileLink* children, std::size_t count);

// "b" + RFC 4648 base32, lower case, no padding.
std::string cidToString(const Cid& cid);

// contentHash with another chunk size and fan-out, to reach three-level trees with small inputs.
// chunk_size 0 is treated as 1 and max_children below 2 as 2 (a fan-out of 1 never ends).
std::string contentHashWithLayout(const std::uint8_t* data, std::size_t size,
                                  std::size_t chunk_size, std::size_t max_children);

}  // namespace detail
}  // namespace springbones
