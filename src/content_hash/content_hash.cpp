// Decentraland content hash, re-implemented from what @dcl/hashing 3.0.4 `hashV1` does: it runs
// ipfs-unixfs-importer (v15 era) with { cidVersion: 1, rawLeaves: true } and the importer's defaults.
// Every constant below is one of those defaults; change any of them and the hashes no longer match
// the ones the catalyst stores. docs/content-hash.md walks through the derivation with examples.
#include "springbones/content_hash.h"

#include <algorithm>

#include "content_hash/cid.h"
#include "content_hash/sha256.h"

namespace springbones {
namespace detail {
namespace {

// The importer's fixed-size chunker default (256 KiB).
constexpr std::size_t kChunkSize = 262144;
// The importer's balanced-layout default, inherited from go-unixfs: an 8 KiB link block divided by
// a rough 47-byte link (34-byte multihash + 8 size + 5 framing) = 174. Not tuned for anything here,
// but it decides the tree shape and therefore every hash above 174 chunks (45,613,056 bytes).
constexpr std::size_t kMaxChildrenPerNode = 174;

constexpr std::uint8_t kCidVersion1 = 0x01;
// rawLeaves: true stores each chunk as-is (codec "raw") instead of wrapping it in a UnixFS dag-pb
// node, so a one-chunk file hashes to its raw CID ("bafkrei...").
constexpr std::uint8_t kCodecRaw = 0x55;
constexpr std::uint8_t kCodecDagPb = 0x70;  // multicodec "dag-pb": inner UnixFS file nodes
constexpr std::uint8_t kMultihashSha256 = 0x12;
constexpr std::uint8_t kSha256Size = 0x20;

// Protobuf keys: (field number << 3) | wire type (0 = varint, 2 = length-delimited).
constexpr std::uint8_t kPbNodeData = 0x0a;        // PBNode.Data = 1, bytes
constexpr std::uint8_t kPbNodeLinks = 0x12;       // PBNode.Links = 2, repeated PBLink
constexpr std::uint8_t kPbLinkHash = 0x0a;        // PBLink.Hash = 1, bytes
constexpr std::uint8_t kPbLinkName = 0x12;        // PBLink.Name = 2, string
constexpr std::uint8_t kPbLinkTsize = 0x18;       // PBLink.Tsize = 3, varint
constexpr std::uint8_t kUnixFsType = 0x08;        // Data.Type = 1, varint
constexpr std::uint8_t kUnixFsFilesize = 0x18;    // Data.filesize = 3, varint
constexpr std::uint8_t kUnixFsBlocksizes = 0x20;  // Data.blocksizes = 4, repeated varint, not packed
constexpr std::uint8_t kUnixFsTypeFile = 2;

std::size_t varintSize(std::uint64_t value) {
  std::size_t size = 1;
  while (value >= 0x80) {
    value >>= 7;
    ++size;
  }
  return size;
}

void appendVarint(std::vector<std::uint8_t>& out, std::uint64_t value) {
  while (value >= 0x80) {
    out.push_back(static_cast<std::uint8_t>(value | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<std::uint8_t>(value));
}

Cid makeCid(std::uint8_t codec, const Sha256Digest& digest) {
  Cid cid;
  cid[0] = kCidVersion1;
  cid[1] = codec;
  cid[2] = kMultihashSha256;
  cid[3] = kSha256Size;
  std::copy(digest.begin(), digest.end(), cid.begin() + 4);
  return cid;
}

// The importer's file reducer: a parent whose links are the children, in order.
FileLink reduceToFileNode(const std::vector<FileLink>& children) {
  const std::vector<std::uint8_t> block = encodeFileNode(children.data(), children.size());
  FileLink node;
  node.cid = makeCid(kCodecDagPb, sha256(block.data(), block.size()));
  // Tsize counts every block below a link, the node's own block included.
  node.tsize = block.size();
  node.file_size = 0;
  for (const FileLink& child : children) {
    node.tsize += child.tsize;
    node.file_size += child.file_size;
  }
  return node;
}

// The importer's balanced layout, fed one leaf at a time. The importer batches all leaves into
// groups of max_children, reduces each group to a node, and repeats on the nodes until one is left.
// Reducing a group as soon as it is full gives the same tree while holding at most max_children
// links per level: a few kilobytes per level, whatever the file size.
class BalancedLayout {
 public:
  explicit BalancedLayout(std::size_t max_children) : max_children_(max_children) {}

  void addLeaf(const FileLink& leaf) { add(0, leaf); }

  // The root once every leaf has been added (at least one must have been).
  FileLink finish() {
    for (std::size_t level = 0; level < levels_.size(); ++level) {
      // A node alone at its level with no full group sent up is the root. At level 0 that is the
      // importer's reduceSingleLeafToSelf: a one-chunk file's CID is its raw leaf's CID.
      if (!levels_[level].sent_up && levels_[level].pending.size() == 1) { return levels_[level].pending.front(); }
      // A trailing partial group becomes a node too, even a group of one: the importer only skips
      // wrapping for a one-chunk file, so 175 leaves give a root over nodes of 174 and of 1 leaf.
      if (!levels_[level].pending.empty()) sendUp(level);
    }
    return FileLink{};  // only reached if no leaf was added; contentHash always adds one
  }

 private:
  struct Level {
    std::vector<FileLink> pending;  // nodes of this level not yet grouped under a parent
    bool sent_up = false;           // whether a parent was already made from this level
  };

  void add(std::size_t level, const FileLink& link) {
    if (level == levels_.size()) levels_.emplace_back();
    levels_[level].pending.push_back(link);
    if (levels_[level].pending.size() == max_children_) sendUp(level);
  }

  void sendUp(std::size_t level) {
    const FileLink parent = reduceToFileNode(levels_[level].pending);
    levels_[level].pending.clear();
    levels_[level].sent_up = true;
    add(level + 1, parent);  // recursion depth is the tree height: log174 of the chunk count
  }

  std::size_t max_children_;
  std::vector<Level> levels_;
};

}  // namespace

Cid rawLeafCid(const std::uint8_t* chunk, std::size_t size) { return makeCid(kCodecRaw, sha256(chunk, size)); }

std::vector<std::uint8_t> encodeFileNode(const FileLink* children, std::size_t count) {
  // @ipld/dag-pb writes Links before Data (the canonical order), whatever the field numbers say.
  // The importer only links children with file bytes; every child here has some, because only
  // the empty file has an empty chunk and that file is a single leaf that never gets a parent.
  std::uint64_t file_size = 0;
  std::size_t data_size = 2;  // Type
  std::size_t block_size = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t link_size = 2 + children[i].cid.size() + 2 + 1 + varintSize(children[i].tsize);
    block_size += 1 + varintSize(link_size) + link_size;
    data_size += 1 + varintSize(children[i].file_size);
    file_size += children[i].file_size;
  }
  data_size += 1 + varintSize(file_size);
  block_size += 1 + varintSize(data_size) + data_size;

  std::vector<std::uint8_t> block;
  block.reserve(block_size);
  for (std::size_t i = 0; i < count; ++i) {
    const FileLink& child = children[i];
    block.push_back(kPbNodeLinks);
    appendVarint(block, 2 + child.cid.size() + 2 + 1 + varintSize(child.tsize));
    block.push_back(kPbLinkHash);
    block.push_back(static_cast<std::uint8_t>(child.cid.size()));
    block.insert(block.end(), child.cid.begin(), child.cid.end());
    // Name is "" but still written (key + zero length): dag-pb encodes a present empty string, and
    // the importer sets Name: "" on every link, so dropping it would change every hash.
    block.push_back(kPbLinkName);
    block.push_back(0);
    block.push_back(kPbLinkTsize);
    appendVarint(block, child.tsize);
  }
  block.push_back(kPbNodeData);
  appendVarint(block, data_size);
  block.push_back(kUnixFsType);
  block.push_back(kUnixFsTypeFile);
  block.push_back(kUnixFsFilesize);
  appendVarint(block, file_size);
  // blocksizes is declared without [packed=true] in unixfs.proto (proto2), so one key per value.
  for (std::size_t i = 0; i < count; ++i) {
    block.push_back(kUnixFsBlocksizes);
    appendVarint(block, children[i].file_size);
  }
  return block;
}

std::string cidToString(const Cid& cid) {
  static constexpr char kAlphabet[] = "abcdefghijklmnopqrstuvwxyz234567";
  std::string text;
  text.reserve(1 + (cid.size() * 8 + 4) / 5);
  text.push_back('b');  // multibase prefix of base32 lower case
  std::uint32_t bits = 0;
  int bit_count = 0;
  for (std::uint8_t byte : cid) {
    bits = (bits << 8) | byte;
    bit_count += 8;
    while (bit_count >= 5) {
      bit_count -= 5;
      text.push_back(kAlphabet[(bits >> bit_count) & 31]);
    }
  }
  if (bit_count > 0) text.push_back(kAlphabet[(bits << (5 - bit_count)) & 31]);  // no '=' padding
  return text;
}

std::string contentHashWithLayout(const std::uint8_t* data, std::size_t size, std::size_t chunk_size,
                                  std::size_t max_children) {
  chunk_size = std::max<std::size_t>(chunk_size, 1);
  max_children = std::max<std::size_t>(max_children, 2);
  BalancedLayout layout(max_children);
  // do/while: the chunker emits one empty chunk for an empty file, so that file still has a leaf.
  std::size_t offset = 0;
  do {
    const std::size_t chunk = std::min(chunk_size, size - offset);
    FileLink leaf;
    leaf.cid = rawLeafCid(data + offset, chunk);  // hashed in place, never copied
    leaf.tsize = chunk;                           // a raw block is the chunk, so both sizes agree
    leaf.file_size = chunk;
    layout.addLeaf(leaf);
    offset += chunk;
  } while (offset < size);
  return cidToString(layout.finish().cid);
}

}  // namespace detail

std::string contentHash(const std::uint8_t* data, std::size_t size) {
  return detail::contentHashWithLayout(data, size, detail::kChunkSize, detail::kMaxChildrenPerNode);
}

}  // namespace springbones
