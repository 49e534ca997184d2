// The fast readers of glTF and springBones text (json_scan.h, used by loadSkeleton and
// parseSpringBonesText) against the nlohmann-based readers they stand in for
// (loadSkeletonChecked, parseSpringBonesTextChecked): on every input both must give the same
// error (code, message, path) or the same skeleton / model entry and warnings, bit for bit.
// Inputs: the fixtures, the fuzz corpora, hand-written edge cases of JSON itself (escapes,
// surrogates, number forms, duplicate keys, NUL padding, nesting), and deterministic mutations
// of small documents, which hit the fast readers' refusals and the nlohmann errors alike.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "json_scan.h"
#include "springbones.h"
#include "test_helpers.h"
#include "transform_math.h"

namespace springbones {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

bool sameBits(const void* a, const void* b, std::size_t n) { return std::memcmp(a, b, n) == 0; }

// Empty when both readers agree, else what differs.
std::string compareSkeletons(const std::string& input) {
  const auto* data = reinterpret_cast<const std::uint8_t*>(input.data());
  Skeleton fast, checked;
  const Error a = loadSkeleton(data, input.size(), fast);
  const Error b = loadSkeletonChecked(data, input.size(), checked);
  if (a.code != b.code || a.message != b.message || a.path != b.path) {
    return "errors differ: fast '" + a.message + "' vs checked '" + b.message + "'";
  }
  if (fast.nodes.size() != checked.nodes.size()) return "node counts differ";
  if (fast.parents_first != checked.parents_first) return "parents_first differs";
  for (std::size_t i = 0; i < fast.nodes.size(); ++i) {
    const SkeletonNode& x = fast.nodes[i];
    const SkeletonNode& y = checked.nodes[i];
    const std::string where = "node " + std::to_string(i) + ": ";
    if (x.name != y.name) return where + "name differs";
    if (x.parent != y.parent || x.children != y.children) return where + "links differ";
    if (!sameBits(&x.rest_local.translation, &y.rest_local.translation, sizeof(glm::vec3)) ||
        !sameBits(&x.rest_local.rotation, &y.rest_local.rotation, sizeof(glm::quat)) ||
        !sameBits(&x.rest_local.scale, &y.rest_local.scale, sizeof(glm::vec3)) ||
        !sameBits(&x.rest_world, &y.rest_world, sizeof(glm::mat4))) {
      return where + "rest transform differs";
    }
  }
  return {};
}

std::string compareMetadata(const std::string& text, const std::string& hash) {
  ModelEntry fast, checked;
  std::vector<Warning> fast_warnings{{"earlier", "a warning already there", ""}}, checked_warnings = fast_warnings;
  const Error a = parseSpringBonesText(text, hash, fast, fast_warnings);
  const Error b = parseSpringBonesTextChecked(text, hash, checked, checked_warnings);
  if (a.code != b.code || a.message != b.message || a.path != b.path) {
    return "errors differ: fast '" + a.message + "' vs checked '" + b.message + "'";
  }
  if (fast_warnings.size() != checked_warnings.size()) return "warning counts differ";
  for (std::size_t i = 0; i < fast_warnings.size(); ++i) {
    const Warning& x = fast_warnings[i];
    const Warning& y = checked_warnings[i];
    if (x.code != y.code || x.message != y.message || x.path != y.path) {
      return "warning " + std::to_string(i) + " differs: " + x.message + " vs " + y.message;
    }
  }
  if (fast.enabled != checked.enabled || fast.path != checked.path || fast.bones.size() != checked.bones.size()) {
    return "entries differ";
  }
  for (std::size_t i = 0; i < fast.bones.size(); ++i) {
    const BoneEntry& x = fast.bones[i];
    const BoneEntry& y = checked.bones[i];
    const std::string where = "entry " + std::to_string(i) + " ('" + y.name + "'): ";
    if (x.name != y.name || fast.entryPath(x) != checked.entryPath(y)) return where + "name or path differs";
    if (x.is_root != y.is_root || x.has_center != y.has_center || x.center != y.center) {
      return where + "isRoot or center differs";
    }
    const BoneParams& p = x.params;
    const BoneParams& q = y.params;
    if (!sameBits(&p.stiffness, &q.stiffness, sizeof(float)) ||
        !sameBits(&p.gravity_power, &q.gravity_power, sizeof(float)) ||
        !sameBits(&p.gravity_dir, &q.gravity_dir, sizeof(glm::vec3)) || !sameBits(&p.drag, &q.drag, sizeof(float))) {
      return where + "params differ";
    }
  }
  return {};
}

// The first key of `models` when the text parses (the fuzz harness's choice), else a fixed one.
std::string firstModelKey(const std::string& text) {
  const json value = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (value.is_object() && value.contains("models") && value["models"].is_object() && !value["models"].empty()) {
    return value["models"].begin().key();
  }
  return "bafkreifixedhash";
}

std::string fileText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A small wearable: nodes with every field we read, and its springBones.
const std::string kGltf =
    R"({"asset":{"version":"2.0","generator":"x"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[)"
    R"({"name":"Avatar_Hips","children":[1,3],"translation":[0,1.25,-0.5],"extras":{"a":[1,{"b":null}]}},)"
    R"({"name":"springbone_hair","children":[2],"rotation":[0,0.7071068,0,0.7071068],"scale":[1,1,1]},)"
    R"({"name":"springbone_tip","translation":[0,-0.05,0]},)"
    R"({"name":"Armature","matrix":[0.01,0,0,0,0,0.01,0,0,0,0,0.01,0,0,0,0,1]}],"meshes":[{"name":"m"}]})";
const std::string kSpringBones =
    R"({"version":1,"models":{"h":{"springbone_hair":{"stiffness":1.5,"gravityPower":0.25,)"
    R"("gravityDir":[0,-1,0],"drag":0.4,"center":"Avatar_Hips","isRoot":true},"springbone_tip":{"drag":1}},)"
    R"("other":{"x":{}}}})";

TEST(LoadFastPath, TakesTheUsualDocumentsItself) {
  EXPECT_TRUE(fastGltfReaderAccepts(reinterpret_cast<const std::uint8_t*>(kGltf.data()), kGltf.size()));
  const std::string padded = kGltf + std::string(3, '\0');  // NUL ends nlohmann's input too
  EXPECT_TRUE(fastGltfReaderAccepts(reinterpret_cast<const std::uint8_t*>(padded.data()), padded.size()));
  const std::vector<std::uint8_t> glb = test::makeGlb(kGltf);
  EXPECT_TRUE(fastGltfReaderAccepts(glb.data(), glb.size()));
  EXPECT_TRUE(fastSpringBonesReaderAccepts(kSpringBones, "h"));
  const std::string fixture = test::readFixtureText("adr_example.metadata.json");
  EXPECT_TRUE(fastSpringBonesReaderAccepts(fixture, firstModelKey(fixture)));
  // Left to the nlohmann path: a byte order mark, a value it reports with a warning, no entry.
  EXPECT_FALSE(fastGltfReaderAccepts(reinterpret_cast<const std::uint8_t*>(("\xef\xbb\xbf" + kGltf).data()),
                                     kGltf.size() + 3));
  EXPECT_FALSE(fastSpringBonesReaderAccepts(R"({"version":1,"models":{"h":{"springbone_a":{"drag":2}}}})", "h"));
  EXPECT_FALSE(fastSpringBonesReaderAccepts(kSpringBones, "missing"));
}

TEST(LoadFastPath, AgreesOnFixturesAndFuzzCorpora) {
  int compared = 0;
  for (const char* name : {"adr_example.glb", "adr_example.gltf", "adr_example_posed.glb", "avatar_hair.glb",
                           "cycle.gltf", "two_parents.gltf", "vrm0_springs.vrm", "vrm10_springs.vrm"}) {
    const std::string bytes = test::readFixtureText(name);
    EXPECT_EQ(compareSkeletons(bytes), "") << name;
    ++compared;
  }
  for (const char* name : {"adr_example.metadata.json", "avatar_hair.metadata.json"}) {
    const std::string text = test::readFixtureText(name);
    const json value = json::parse(text);
    // The file is the item's data.springBones or holds it; either way compare what loadRig gets.
    const json& springBones = value.contains("models") ? value : value.at("data").at("springBones");
    for (const std::string& sb_text : {springBones.dump(), springBones.dump(2), text}) {
      EXPECT_EQ(compareMetadata(sb_text, firstModelKey(sb_text)), "") << name;
    }
    ++compared;
  }
  const fs::path fuzz = fs::path(SPRINGBONES_FIXTURES_DIR) / ".." / "fuzz";
  const std::string separator = "\n@@springBones@@\n";
  for (const char* kind : {"corpus", "regressions"}) {
    for (const char* target : {"glb_metadata", "metadata"}) {
      const fs::path dir = fuzz / kind / target;
      if (!fs::is_directory(dir)) continue;
      for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string input = fileText(entry.path());
        std::string glb = input, text = input;
        if (std::string(target) == "glb_metadata") {
          const std::size_t at = input.rfind(separator);
          glb = input.substr(0, at);
          text = at == std::string::npos ? "null" : input.substr(at + separator.size());
          EXPECT_EQ(compareSkeletons(glb), "") << entry.path();
        }
        EXPECT_EQ(compareMetadata(text, firstModelKey(text)), "") << entry.path();
        EXPECT_EQ(compareMetadata(text, "bafkreifixedhash"), "") << entry.path();
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 40);
}

TEST(LoadFastPath, AgreesOnJsonEdgeCases) {
  const std::string head = R"({"asset":{"version":"2.0"},"nodes":[)";
  const std::vector<std::string> nodes = {
      R"({"name":"a\"b\\c\/d\b\f\n\r\t\u00e9\u4e2d\ud83d\ude00"})",  // every escape, a surrogate pair
      R"({"name":"\ud800"})", R"({"name":"\udc00"})", R"({"name":"\ud800\u0041"})", R"({"name":"\u00"})",
      R"({"name":"\x"})", "{\"name\":\"tab\there\"}", "{\"name\":\"caf\xc3\xa9 \xe4\xb8\xad \xf0\x9f\x98\x80\"}",
      "{\"name\":\"\xc3\"}", "{\"name\":\"\xe0\x80\xaf\"}", "{\"name\":\"\xed\xa0\x80\"}", "{\"name\":\"\xf4\x90\x80\x80\"}",
      "{\"name\":\"\xc0\xaf\"}", "{\"name\":\"\x7f\"}", R"({"name":"\u0000x"})",
      R"({"translation":[-0,0.0,-0.0]})", R"({"translation":[1E2,1e-2,1.5e+3]})", R"({"translation":[01,0,0]})",
      R"({"translation":[1.,0,0]})", R"({"translation":[.5,0,0]})", R"({"translation":[+1,0,0]})",
      R"({"translation":[1e400,0,0]})", R"({"translation":[3.4028235e38,-3.4028236e38,0]})",
      R"({"translation":[0.1000000000000000055511151231257827021181583404541015625,1e-400,123456789012345678901234567890]})",
      R"({"translation":[9007199254740993,-9223372036854775808,18446744073709551615]})",
      R"({"translation":[-9223372036854775809,18446744073709551616,2.2250738585072011e-308]})",
      R"({"translation":[0.30000000000000004,1e22,1e23]})", R"({"translation":[1,2]})", R"({"translation":[1,2,3,4]})",
      R"({"translation":[1,2,"3"]})", R"({"translation":{"0":1}})", R"({"rotation":[0,0,0,0]})",
      R"({"rotation":[1e30,1e30,0,0]})", R"({"matrix":[1,0,0,0,0,1,0,0,0,0,1,0,5,6,7,1],"translation":[1,1,1]})",
      R"({"children":[]})", R"({"children":[1.0]})", R"({"children":[-1]})", R"({"children":[262144]})",
      R"({"children":[262145]})", R"({"children":[1e0]})", R"({"children":[-0]})", R"({"children":[0]})",
      R"({"name":"a","name":"b"})", R"({"translation":[1,0,0],"translation":[2,0,0]})", R"({"name":5})",
      R"({"name":null})", R"({"extras":[[[[[[[[[[[[{"deep":true}]]]]]]]]]]]]})", R"({"extras":[1,]})",
      R"({"extras":{"a":1,}})", R"({"extras":tru})", R"({"extras":nul})", R"({"extras":"\q"})", R"({})", R"([])",
      R"(5)", R"({"name":"a"} )"};
  int compared = 0, fast = 0;
  for (const std::string& n : nodes) {
    for (const std::string& doc : {head + n + "]}", head + n + "," + n + "]}"}) {
      EXPECT_EQ(compareSkeletons(doc), "") << doc;
      fast += fastGltfReaderAccepts(reinterpret_cast<const std::uint8_t*>(doc.data()), doc.size());
      ++compared;
    }
  }
  // The fast reader took the valid ones itself (escapes, UTF-8, number forms, NUL padding...).
  EXPECT_GE(fast, 30);
  const std::vector<std::string> documents = {
      kGltf, kGltf + std::string(3, '\0'), kGltf + std::string("\0garbage", 8), kGltf + " x", "\xef\xbb\xbf" + kGltf,
      R"({"asset":{"version":"2.0"}})", R"({"asset":{"version":"2.0"},"nodes":[]})", R"({"asset":{},"nodes":[]})",
      R"({"asset":{"version":2},"nodes":[]})", R"({"asset":"2.0","nodes":[]})", R"({"nodes":[]})",
      R"({"asset":{"version":"2.0","version":"1.0"},"nodes":[]})", R"({"asset":{"version":"2.0"},"asset":{"version":"2.0"}})",
      R"({"asset":{"version":"2.0"},"nodes":[{"name":"a"}],"nodes":[{"name":"b"}]})",
      R"({"asset":{"version":"2.0"},"nodes":{"0":{}}})", R"({"asset":{"version":"2.0"},"nodes":[1]})",
      R"({"asset":{"version":"2.0"},"nodes":[{"children":[0]}]})", R"({"asset":{"version":"2.0"},"nodes":[{"children":[1]},{"children":[0]}]})",
      R"({"asset":{"version":"2.0"},"nodes":[{"children":[2]},{"children":[2]},{}]})", "{\"asset\":{\"version\":\"2.0\"}}\n\r\t ",
      R"( { "asset" : { "version" : "2.0" } , "nodes" : [ { "name" : "a" , "children" : [ 1 ] } , { } ] } )",
      std::string(R"({"asset":{"version":"2.0"},"extras":)") + std::string(600, '[') + std::string(600, ']') + "}",
  };
  for (const std::string& doc : documents) {
    EXPECT_EQ(compareSkeletons(doc), "") << doc;
    const std::vector<std::uint8_t> glb = test::makeGlb(doc);
    EXPECT_EQ(compareSkeletons(std::string(glb.begin(), glb.end())), "") << doc;
    ++compared;
  }

  const std::vector<std::string> entries = {
      R"({"stiffness":1,"gravityPower":0.5,"gravityDir":[0,-1,0],"drag":0.4,"center":null,"isRoot":false})",
      R"({})", R"({"stiffness":4,"gravityPower":2,"drag":0,"gravityDir":[10,-10,0.5]})", R"({"stiffness":4.0000001})",
      R"({"stiffness":-0})", R"({"stiffness":-0.0})", R"({"drag":1e-400})", R"({"drag":1e400})", R"({"drag":"0.5"})",
      R"({"gravityDir":[0,0,0]})", R"({"gravityDir":[1e-10,0,0]})", R"({"gravityDir":[11,0,0]})", R"({"gravityDir":[1,2]})",
      R"({"gravityDir":[0.3,0.4,0.5]})", R"({"center":"Avatar_Hips"})", R"({"center":5})", R"({"center":""})",
      R"({"isRoot":true})", R"({"isRoot":null})", R"({"isRoot":1})", R"({"stiffness":1,"stiffness":2})",
      R"({"extra":{"nested":[1,2,{"x":"\u00e9"}]},"drag":0.1})", R"([])", R"(null)", R"(1)",
      R"({"center":"a\/b~c"})"};
  const std::vector<std::string> names = {"springbone_a", "springbone_b", "a/b~c", "\\u00e9springbone", "Z", "é"};
  for (const std::string& e : entries) {
    std::string model = "{";
    for (std::size_t i = 0; i < names.size(); ++i) model += (i ? ",\"" : "\"") + names[names.size() - 1 - i] + "\":" + e;
    model += "}";
    for (const std::string& text :
         {R"({"version":1,"models":{"h":)" + model + "}}", R"({"models":{"x":1,"h":)" + model + R"(},"version":1.0})",
          R"({"version":1,"models":{"h":)" + model + R"(,"h":{}}})", R"({"version":2,"models":{"h":)" + model + "}}"}) {
      EXPECT_EQ(compareMetadata(text, "h"), "") << text;
      EXPECT_EQ(compareMetadata(text, "missing"), "") << text;
      fast += fastSpringBonesReaderAccepts(text, "h");
      ++compared;
    }
  }
  for (const std::string& text :
       {std::string("null"), std::string("{}"), std::string(R"({"version":1})"), std::string(R"({"version":1,"models":[]})"),
        std::string(R"({"version":"1","models":{"h":{}}})"), std::string(R"({"version":1,"models":{"h":[]}})"),
        std::string(R"({"version":1,"models":{"h":{}},"version":1})"), std::string(R"({"version":1,"models":{"h":{}}} x)"),
        std::string("{\"version\":1,\"models\":{\"h\":{}}}\0\0", 33), std::string("\xef\xbb\xbf{\"version\":1,\"models\":{\"h\":{}}}"),
        std::string(R"({"version":1,"models":{"\u0068":{"springbone_x":{}}}})"), kSpringBones}) {
    EXPECT_EQ(compareMetadata(text, "h"), "") << text;
    ++compared;
  }
  EXPECT_GT(compared, 200);
}

// Byte-level mutations (replace, insert, delete, truncate) of small valid documents: most break
// them somewhere the fast readers must refuse, some keep them valid with other values.
TEST(LoadFastPath, AgreesOnMutatedDocuments) {
  std::mt19937 rng(20261123);
  const std::string interesting = "\"\\,:{}[]0123456789-+.eEu tfn \x01\xc3\xa9\xff";
  const auto mutate = [&](std::string s) {
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int k = 0; k < edits && !s.empty(); ++k) {
      const std::size_t at = rng() % s.size();
      const char c = interesting[rng() % interesting.size()];
      switch (rng() % 4) {
        case 0: s[at] = c; break;
        case 1: s.insert(s.begin() + static_cast<std::ptrdiff_t>(at), c); break;
        case 2: s.erase(at, 1); break;
        default: s.resize(at); break;
      }
    }
    return s;
  };
  int fast_ok = 0;
  for (int i = 0; i < 3000; ++i) {
    const std::string doc = mutate(kGltf);
    EXPECT_EQ(compareSkeletons(doc), "") << doc;
    const std::string text = mutate(kSpringBones);
    EXPECT_EQ(compareMetadata(text, "h"), "") << text;
    Skeleton s;
    fast_ok += loadSkeleton(reinterpret_cast<const std::uint8_t*>(doc.data()), doc.size(), s) ? 0 : 1;
  }
  // Some mutants must still load, or the comparison only ever saw errors.
  EXPECT_GT(fast_ok, 100);
}

}  // namespace
}  // namespace springbones

namespace springbones {
namespace {

// linkHierarchy multiplies the rest matrices with its own scalar code (no out-of-line glm calls
// in WebAssembly); it must give glm's product bit for bit, zero signs included.
TEST(LoadFastPath, RestWorldIsGlmsProductToTheBit) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  std::string text = R"({"asset":{"version":"2.0"},"nodes":[)";
  const int count = 200;
  for (int i = 0; i < count; ++i) {
    char node[512];
    if (i % 7 == 3) {
      std::snprintf(node, sizeof node, R"({"matrix":[%.9g,%.9g,0,0,%.9g,%.9g,0,0,0,0,-0.0,1,%.9g,%.9g,%.9g,1])",
                    u(rng), u(rng), u(rng), u(rng), u(rng), u(rng), u(rng));
    } else {
      std::snprintf(node, sizeof node,
                    R"({"translation":[%.9g,%.9g,-0.0],"rotation":[%.9g,%.9g,%.9g,%.9g],"scale":[%.9g,1,%.9g])", u(rng),
                    u(rng), u(rng), u(rng), u(rng), u(rng), u(rng), u(rng));
    }
    text += (i ? "," : "") + std::string(node);
    // A chain with side branches: node i's parent is i - 1 or i - 2.
    const int child_a = i + 1, child_b = i + 2;
    if (i % 2 == 0 && child_b < count) {
      text += ",\"children\":[" + std::to_string(child_a) + "," + std::to_string(child_b) + "]}";
    } else if (i % 2 == 0 && child_a < count) {
      text += ",\"children\":[" + std::to_string(child_a) + "]}";
    } else {
      text += "}";
    }
  }
  text += "]}";
  Skeleton s;
  ASSERT_FALSE(test::loadText(text, s)) << text.substr(0, 200);
  int checked = 0;
  for (int i : s.parents_first) {
    const SkeletonNode& n = s.nodes[i];
    const glm::mat4 local = composeTransform(n.rest_local);
    const glm::mat4 expected = n.parent < 0 ? local : s.nodes[n.parent].rest_world * local;
    EXPECT_TRUE(sameBits(&expected, &n.rest_world, sizeof(glm::mat4))) << "node " << i;
    checked += n.parent >= 0;
  }
  EXPECT_GT(checked, 50);
}

}  // namespace
}  // namespace springbones

namespace springbones {
namespace {

// The fast metadata reader sorts entry names by 8 bytes after their common prefix, whole names
// only on a tie: names that differ only past those 8 bytes, are prefixes of one another, hold
// bytes above 0x7f or a \u0000, in shuffled order, must come out in nlohmann's (byte-wise) order,
// and a repeated name must still be left to the checked reader.
// springBones text with one entry per name, in the given order.
std::string metadataWithEntries(const std::vector<std::string>& names) {
  std::string text = R"({"version":1,"models":{"h":{)";
  for (std::size_t i = 0; i < names.size(); ++i) {
    text += (i ? ",\"" : "\"") + names[i] + R"(":{"stiffness":1,"drag":0.5})";
  }
  return text + "}}}";
}

TEST(LoadFastPath, SortsEntryNamesAsNlohmannDoes) {
  std::vector<std::string> names = {"springbone_", "springbone_a", "springbone_a\\u0000", "springbone_a\\u0001",
                                    "springbone_\\u00e9", "springbone_\\u00ff", "springbone_~1", "springbone_a/b"};
  for (int i = 0; i < 40; ++i) {
    names.push_back("springbone_" + std::to_string(i));
    names.push_back("springbone_" + std::to_string(i) + "_longer_than_eight_" + std::to_string(i % 3));
    names.push_back("springbone_abcdefgh" + std::to_string(i * 7));
  }
  std::mt19937 rng(11);
  for (int round = 0; round < 5; ++round) {
    std::shuffle(names.begin(), names.end(), rng);
    const std::string text = metadataWithEntries(names);
    EXPECT_TRUE(fastSpringBonesReaderAccepts(text, "h"));
    EXPECT_EQ(compareMetadata(text, "h"), "");
    // The same with one name twice: the checked reader decides (nlohmann keeps the last).
    const std::string repeated = text.substr(0, text.size() - 3) + ",\"" + names[round] + R"(":{"drag":1}}}})";
    EXPECT_FALSE(fastSpringBonesReaderAccepts(repeated, "h"));
    EXPECT_EQ(compareMetadata(repeated, "h"), "");
  }
  // Random names (the sort goes byte by byte through whichever of the 8 bytes differ): 2,000
  // of 0 to 12 letters after the prefix, so that every byte varies and many names tie on all 8.
  std::uniform_int_distribution<int> length(0, 12), letter('a', 'd');
  std::set<std::string> unique;
  while (unique.size() < 2000) {
    std::string name = "springbone_";
    for (int k = length(rng); k > 0; --k) name += static_cast<char>(letter(rng));
    unique.insert(name);
  }
  std::vector<std::string> random_names(unique.begin(), unique.end());
  std::shuffle(random_names.begin(), random_names.end(), rng);
  const std::string text = metadataWithEntries(random_names);
  EXPECT_TRUE(fastSpringBonesReaderAccepts(text, "h"));
  EXPECT_EQ(compareMetadata(text, "h"), "");
  // No common prefix at all, and a single entry.
  EXPECT_EQ(compareMetadata(R"({"version":1,"models":{"h":{"b":{},"a":{},"":{},"ab":{}}}})", "h"), "");
  EXPECT_TRUE(fastSpringBonesReaderAccepts(R"({"version":1,"models":{"h":{"b":{},"a":{},"":{},"ab":{}}}})", "h"));
  EXPECT_EQ(compareMetadata(R"({"version":1,"models":{"h":{"only":{}}}})", "h"), "");
}

}  // namespace
}  // namespace springbones

namespace springbones {
namespace {

double scanned(const std::string& token) {
  JsonScan scan(token.data(), token.data() + token.size());
  JsonNumber n;
  EXPECT_TRUE(scan.number(n) && scan.atEnd()) << token;
  return n.value;
}

// The fast reader reads long significands (up to 19 digits, as JavaScript and Python print
// doubles) with exact integer arithmetic instead of strtod: it must return strtod's double, ties
// to even included, for every token we try.
TEST(LoadFastPath, ReadsLongDecimalsAsStrtodDoes) {
  std::mt19937_64 rng(13);
  int failures = 0;
  const auto check = [&](const std::string& token) {
    const double expected = std::strtod(token.c_str(), nullptr);
    const double got = scanned(token);
    if (std::memcmp(&expected, &got, sizeof got) != 0 && ++failures <= 10) {
      ADD_FAILURE() << token << ": " << got << " vs strtod " << expected;
    }
  };
  for (int i = 0; i < 200000; ++i) {
    const int length = 1 + static_cast<int>(rng() % 19);
    std::string digits = std::to_string(1 + rng() % 9);
    while (static_cast<int>(digits.size()) < length) digits += static_cast<char>('0' + rng() % 10);
    const int point = static_cast<int>(rng() % (length + 1));
    std::string token = (rng() & 1 ? "-" : "") + digits.substr(0, point > 0 ? point : 1);
    if (point < length) token += "." + digits.substr(point > 0 ? point : 1);
    if (token.back() == '.') token += '0';
    if (rng() % 3 == 0) token += "e" + std::to_string(static_cast<int>(rng() % 50) - 30);
    check(token);
  }
  // The doubles JavaScript prints, and the halfway points between neighbouring doubles (ties),
  // written with up to 19 significant digits.
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  for (int i = 0; i < 50000; ++i) {
    char text[64];
    const double d = u(rng) * std::pow(10.0, static_cast<int>(rng() % 30) - 20);
    std::snprintf(text, sizeof text, "%.17g", d);
    check(text);
    std::snprintf(text, sizeof text, "%.19g", d);
    check(text);
  }
  for (const char* token : {"9007199254740993.0", "9007199254740995.0", "9007199254740993.00000000001",
                            "0.30000000000000004", "1.2000000000000002", "100.10000000000001",
                            "4.9406564584124654e-30", "1.7976931348623157e19", "123456789012345678.9e-27",
                            "18446744073709551615e19", "1844674407370955161.5", "0.1000000000000000055511151231257827"}) {
    check(token);
  }
}

}  // namespace
}  // namespace springbones
