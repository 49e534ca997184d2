// The pieces of contentHash (springbones/content_hash.h): the blocks and CIDs of a file's DAG, for
// the tests to check intermediate bytes against the worked example of docs/content-hash.md and to
// exercise deep trees with small chunks.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace springbones {

namespace detail {

using Cid = std::array<std::uint8_t, 36>;  // 0x01 codec 0x12 0x20 + sha256: CIDv1, sha2-256

// A node of the file DAG as its parent sees it (one PBLink plus one UnixFS blocksize).
struct FileLink {
  Cid cid;                  ///< CID bytes of the child block
  std::uint64_t tsize;      ///< bytes of every block in the child's subtree (PBLink Tsize)
  std::uint64_t file_size;  ///< file bytes the child covers (UnixFS blocksize)
};

// The CID of a chunk stored as a raw block (codec 0x55).
Cid rawLeafCid(const std::uint8_t* chunk, std::size_t size);

// The dag-pb block of a UnixFS file node with these children, in order.
std::vector<std::uint8_t> encodeFileNode(const FileLink* children, std::size_t count);

// "b" + RFC 4648 base32, lower case, no padding.
std::string cidToString(const Cid& cid);

// contentHash with another chunk size and fan-out, to reach three-level trees with small inputs.
// chunk_size 0 is treated as 1 and max_children below 2 as 2 (a fan-out of 1 never ends).
std::string contentHashWithLayout(const std::uint8_t* data, std::size_t size, std::size_t chunk_size,
                                  std::size_t max_children);

}  // namespace detail
}  // namespace springbones
