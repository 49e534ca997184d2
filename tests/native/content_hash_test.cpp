// contentHash against Decentraland's own implementation.
//
// Every expected CID below was printed by scripts/reference/content_hash_reference.mjs, which runs `hashV1`
// of npm @dcl/hashing 3.0.4 (and, for the small-layout table, the ipfs-unixfs-importer bundled in
// it). The two worked examples of docs/content-hash.md are among them.
// To regenerate: npm install && node scripts/reference/content_hash_reference.mjs
#include "springbones/content_hash.h"
#include "content_hash/cid.h"
#include "test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace springbones {
namespace {

// The script's patterns: fill07(n) is n bytes of 0x07; mod251(n) is byte i = i % 251.
std::vector<std::uint8_t> fill07(std::size_t size) { return std::vector<std::uint8_t>(size, 0x07); }

std::vector<std::uint8_t> mod251(std::size_t size) {
  std::vector<std::uint8_t> bytes(size);
  for (std::size_t i = 0; i < size; ++i) bytes[i] = static_cast<std::uint8_t>(i % 251);
  return bytes;
}

// mod251 of every size is a prefix of the longest one, so the big cases share one 46 MB buffer.
constexpr std::size_t kLargestInput = 46000000;
const std::vector<std::uint8_t>& largeMod251() {
  static const std::vector<std::uint8_t> bytes = mod251(kLargestInput);
  return bytes;
}

std::string hashOf(const std::vector<std::uint8_t>& bytes) { return contentHash(bytes.data(), bytes.size()); }

std::string hashOfText(const std::string& text) {
  return contentHash(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

using test::toHex;

TEST(ContentHash, HelloworldIsItsRawLeafCid) {
  EXPECT_EQ(hashOfText("helloworld"), "bafkreietnimfzkvcm25zzpuyd2pals3yzvzswczsqdvzirasxnxy7dyhv4");
}

TEST(ContentHash, RawLeafCidIsVersionCodecMultihashAndSha256) {
  const std::string text = "helloworld";
  EXPECT_EQ(toHex(detail::rawLeafCid(reinterpret_cast<const std::uint8_t*>(text.data()), text.size())),
            "01551220936a185caaa266bb9cbe981e9e05cb78cd732b0b3280eb944412bb6f8f8f07af");
}

TEST(ContentHash, EmptyInputWithNullDataIsTheRawCidOfNothing) {
  // The importer's chunker still emits one empty chunk, so the root is sha256("") as a raw leaf.
  EXPECT_EQ(contentHash(nullptr, 0), "bafkreihdwdcefgh4dqkjv67uzcmw7ojee6xedzdetojuzjevtenxquvyku");
}

TEST(ContentHash, OneByteIsARawLeaf) {
  EXPECT_EQ(hashOf(mod251(1)), "bafkreidogqfzz75tpkmjzjke425xqcrmpcib2p5tg44hnbirumdbpl5adu");
}

TEST(ContentHash, ExactlyOneChunkStaysARawLeaf) {
  EXPECT_EQ(hashOf(fill07(262144)), "bafkreibwg653s7uy2ae7fpsnbvffbzzughlla6z63y4yfhqjxp2wnklsua");
}

TEST(ContentHash, OneByteOverAChunkBecomesADagPbRoot) {
  EXPECT_EQ(hashOf(fill07(262145)), "bafybeihldj5jykexbnvf5jx3cm2pjlqqa3hwyc5d6wo2y7ujlk7qjjgzlu");
}

TEST(ContentHash, TwoUnequalChunksMatchTheReference) {
  EXPECT_EQ(hashOf(fill07(300000)), "bafybeifkhqdf426lf6kl5oshczyo2ahhhib6zxruehy2yo72ay74kukg3q");
}

TEST(ContentHash, RootBlockOfTwoUnequalChunksMatchesTheWorkedExampleByteForByte) {
  const std::vector<std::uint8_t> bytes = fill07(300000);
  detail::FileLink leaves[2];
  leaves[0].cid = detail::rawLeafCid(bytes.data(), 262144);
  leaves[0].tsize = leaves[0].file_size = 262144;
  leaves[1].cid = detail::rawLeafCid(bytes.data() + 262144, 37856);
  leaves[1].tsize = leaves[1].file_size = 37856;
  EXPECT_EQ(detail::cidToString(leaves[0].cid), "bafkreibwg653s7uy2ae7fpsnbvffbzzughlla6z63y4yfhqjxp2wnklsua");
  EXPECT_EQ(detail::cidToString(leaves[1].cid), "bafkreihmeryjakzkeedwajzr3jez6usp3krva6s5adaoxghprwa4nbwiye");

  const std::vector<std::uint8_t> block = detail::encodeFileNode(leaves, 2);
  // Two PBLinks {Hash, Name "", Tsize}, then Data = UnixFS {Type 2, filesize 300000,
  // blocksizes 262144, 37856} = 080218e0a7122080801020e0a702.
  EXPECT_EQ(block.size(), 108u);
  EXPECT_EQ(toHex(block),
            "122c0a24015512203637bbb97e98d009f2be4d0d4a50e73431d6b07b3ede39829e09bbf566a972a0120018"
            "808010122c0a2401551220ec2470902b2a2107602731da499f524fdaa3507a5d00c0eb98ef8d81c686c8c1"
            "120018e0a7020a0e080218e0a7122080801020e0a702");
}

TEST(ContentHash, OneMillionBytesMatchTheReference) {
  EXPECT_EQ(contentHash(largeMod251().data(), 1000000), "bafybeibx62obrkybp46hx3ivh53q4rnptgkunpgtwiib5lfelfgt2ekihm");
}

TEST(ContentHash, ExactlyOneHundredSeventyFourChunksFitUnderOneRoot) {
  EXPECT_EQ(contentHash(largeMod251().data(), 174 * 262144),
            "bafybeihpe5snhzneq7xs53nivmsopto5lrogo3wjynauqylqeym5a3irbm");
}

TEST(ContentHash, OneHundredSeventyFiveChunksBuildATwoLevelTree) {
  // Root over a node of 174 leaves and a node wrapping the single last leaf.
  EXPECT_EQ(contentHash(largeMod251().data(), 174 * 262144 + 1),
            "bafybeib4y7ghw2rq7bracc4xwtxrbzo7cfvagdpte2tmrkgwl6dyard3cm");
}

TEST(ContentHash, FortySixMegabytesMatchTheReference) {
  EXPECT_EQ(contentHash(largeMod251().data(), kLargestInput),
            "bafybeic5kla6qndxklmtnmyhxbbczxtds4anbkxkoetpoumt25uckbsy54");
}

TEST(ContentHash, ReadsOnlyTheGivenRange) {
  // The same bytes at another address, followed by other bytes, hash the same.
  std::vector<std::uint8_t> padded(1 + 300000 + 5, 0xee);
  std::fill(padded.begin() + 1, padded.begin() + 1 + 300000, std::uint8_t{0x07});
  EXPECT_EQ(contentHash(padded.data() + 1, 300000), "bafybeifkhqdf426lf6kl5oshczyo2ahhhib6zxruehy2yo72ay74kukg3q");
}

TEST(ContentHash, IsBase32LowerCaseWithoutPadding) {
  const std::string cid = hashOf(fill07(300000));
  ASSERT_EQ(cid.size(), 59u);  // 'b' + ceil(36 bytes * 8 / 5)
  EXPECT_EQ(cid.find_first_not_of("abcdefghijklmnopqrstuvwxyz234567"), std::string::npos);
}

// Small chunks and fan-outs reach trees three and more levels deep (a real three-level tree needs
// 7.9 GB). Reference: section 2 of scripts/reference/content_hash_reference.mjs, input mod251(size).
struct LayoutCase {
  std::size_t chunk_size;
  std::size_t max_children;
  std::size_t size;
  const char* cid;
};

constexpr LayoutCase kLayoutCases[] = {
    {4, 3, 0, "bafkreihdwdcefgh4dqkjv67uzcmw7ojee6xedzdetojuzjevtenxquvyku"},
    {4, 3, 3, "bafkreifojmzibzlof6xyh5auu3r5vpu5l67brf3fitaf73isdlglqw2t7q"},
    {4, 3, 4, "bafkreiafj3pmdubbd5re73imxsu5j6kabmheshcdoqvpfrnqvpv7bsmq3a"},
    {4, 3, 5, "bafybeidoaxjtfzmllhcway5ubogf3onacj5hcjxkps6ltqkicxj5degtta"},
    {4, 3, 12, "bafybeiescpchc5ia7pu7ztozfeiu6k4yith5dbt3r43xshnyudv7krmtae"},
    {4, 3, 13, "bafybeigioqx7mhmr5omwrkizhlha6jprh2gzlqmazplk4cj2ezmbx6lhei"},
    {4, 3, 36, "bafybeiazbw7qde46yxbdyyv4rzu3cbrk2cf7f3h7vtbpbzhooueqfws6ti"},
    {4, 3, 37, "bafybeidiwnloirt3sptf4j5vz6iif5pod6yee4z23t57sftychzrp2n4ge"},
    {4, 3, 108, "bafybeifkinfsm2fujjoekag7yheqoh2modzg4md4d3wlotmykqz3giqbay"},
    {4, 3, 109, "bafybeihqjgih5vr3po3xckv2yf67fsl7qf6mgclby5ik7to5zm6knpzbli"},
    {4, 3, 400, "bafybeian6vpf7wqarrllb5c7bo7etyd55vnkp6s2l36225zis2fx6f4tzy"},
    {4, 3, 1001, "bafybeicvq6adokwkgqummhlmiq2rvtttp52uvgh5o5v7eosiflkp3sk3wy"},
    {1, 2, 2, "bafybeif5uiwwtcp4lhepsst74pn5orww7ih6bbt7thh7qatkbav4skkvui"},
    {1, 2, 3, "bafybeigpgqb7xsccbge2ns342xiqg4n2hm74gdqujozgjcuiavrcttonnu"},
    {1, 2, 5, "bafybeicadlxgx7xh6fkbrn4hxhhjksh7cffdss7vvhpxtxnbh76gs5w2ny"},
    {1, 2, 8, "bafybeigw2mknk7mgqaxiuqmkuxgp3f3fcsfqgydue22ppzuicu6hyf67gy"},
    {1, 2, 17, "bafybeid6kj66v24clfstswt4o6azgnvdghu3zbnidp5unhu4njowvflcom"},
    {1, 174, 174, "bafybeidlzvjwgufajwqsgrxxelmrmpuaglu2aql3kppzt2r2bfj4jiuriy"},
    {1, 174, 175, "bafybeiblelyoch766vusr4mm7tbkrnzzt4jjv3m3cvlvf7w4d53ktylb6q"},
    {1, 174, 174 * 174, "bafybeia2ohid45n7xjzmb27t4cxaqmubuwru7ysbvtltio5kemply5a22i"},
    // 174 * 174 + 1 leaves: 175 first-level nodes, so 2 second-level nodes under a third-level root.
    {1, 174, 174 * 174 + 1, "bafybeifierymatnzcqg5sirstva2l2p6yi5qygqzwr7liwoxroombtuckm"},
};

TEST(ContentHash, DeepTreesWithSmallLayoutsMatchTheImporter) {
  for (const LayoutCase& c : kLayoutCases) {
    EXPECT_EQ(detail::contentHashWithLayout(largeMod251().data(), c.size, c.chunk_size, c.max_children), c.cid)
        << "chunk " << c.chunk_size << ", fan-out " << c.max_children << ", size " << c.size;
  }
}

TEST(ContentHash, DegenerateLayoutParametersAreClampedInsteadOfLooping) {
  const std::uint8_t* data = largeMod251().data();
  EXPECT_EQ(detail::contentHashWithLayout(data, 17, 0, 2), detail::contentHashWithLayout(data, 17, 1, 2));
  EXPECT_EQ(detail::contentHashWithLayout(data, 17, 1, 0), detail::contentHashWithLayout(data, 17, 1, 2));
  EXPECT_EQ(detail::contentHashWithLayout(data, 17, 1, 1), detail::contentHashWithLayout(data, 17, 1, 2));
}

TEST(ContentHash, NeverThrowsForSmallSizesAroundChunkBoundaries) {
  for (std::size_t size : {0u, 1u, 2u, 262143u, 262144u, 262145u, 524288u, 524289u}) {
    EXPECT_NO_THROW(contentHash(largeMod251().data(), size)) << size;
  }
}

}  // namespace
}  // namespace springbones
