// The fast reader of springBones text (json_scan.h, used by parseSpringBonesText) against the
// nlohmann-based reader it stands in for (parseSpringBonesTextChecked): on every input both must
// give the same error (code, message, path) or the same model entry and warnings, bit for bit.
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

// A small springBones.
const std::string kSpringBones =
    R"({"version":1,"models":{"h":{"springbone_hair":{"stiffness":1.5,"gravityPower":0.25,)"
    R"("gravityDir":[0,-1,0],"drag":0.4,"center":"Avatar_Hips","isRoot":true},"springbone_tip":{"drag":1}},)"
    R"("other":{"x":{}}}})";

TEST(LoadFastPath, TakesTheUsualDocumentsItself) {
  EXPECT_TRUE(fastSpringBonesReaderAccepts(kSpringBones, "h"));
  const std::string fixture = test::readFixtureText("adr_example.metadata.json");
  EXPECT_TRUE(fastSpringBonesReaderAccepts(fixture, firstModelKey(fixture)));
  // Left to the nlohmann path: a value it reports with a warning, no entry.
  EXPECT_FALSE(fastSpringBonesReaderAccepts(R"({"version":1,"models":{"h":{"springbone_a":{"drag":2}}}})", "h"));
  EXPECT_FALSE(fastSpringBonesReaderAccepts(kSpringBones, "missing"));
}

TEST(LoadFastPath, AgreesOnFixturesAndFuzzCorpora) {
  int compared = 0;
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
        std::string text = input;
        if (std::string(target) == "glb_metadata") {
          const std::size_t at = input.rfind(separator);
          text = at == std::string::npos ? "null" : input.substr(at + separator.size());
        }
        EXPECT_EQ(compareMetadata(text, firstModelKey(text)), "") << entry.path();
        EXPECT_EQ(compareMetadata(text, "bafkreifixedhash"), "") << entry.path();
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 32);
}

TEST(LoadFastPath, AgreesOnJsonEdgeCases) {
  int compared = 0, fast = 0;
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
  EXPECT_GT(compared, 100);
  // The fast reader took the valid ones itself.
  EXPECT_GT(fast, 20) << fast;
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
    const std::string text = mutate(kSpringBones);
    EXPECT_EQ(compareMetadata(text, "h"), "") << text;
    ModelEntry entry;
    std::vector<Warning> warnings;
    fast_ok += parseSpringBonesText(text, "h", entry, warnings) ? 0 : 1;
  }
  // Some mutants must still load, or the comparison only ever saw errors.
  EXPECT_GT(fast_ok, 100);
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
