// readSpringBonesEntries (json_scan.h): the springBones entries web/springbones.js hands over for
// an object instead of JSON text. For a layout it takes, the model entry and warnings must be
// those parseSpringBonesText gives for the same entries as text; anything else (a value the text
// readers would warn about, a repeated name, a layout that does not add up) must be refused with
// nothing written, because the JS then sends the text and the core reports from there.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "json_scan.h"
#include "springbones.h"

namespace springbones {
namespace {

// One entry as the JS encodes it: values (only those whose flag is set matter), flags, strings.
struct Entry {
  std::string name;
  double values[6] = {1, 0.5, 0.4, 0, -1, 0};  // stiffness, gravityPower, drag, gravityDir
  std::uint32_t flags = kEntryStiffness | kEntryGravityPower | kEntryDrag | kEntryGravityDir;
  std::string center;
};

void putU32(std::vector<std::uint8_t>& out, std::size_t at, std::uint32_t v) { std::memcpy(&out[at], &v, 4); }

// The layout of json_scan.h, as web/springbones.js (encodeEntries) writes it.
std::vector<std::uint8_t> encode(const std::vector<Entry>& entries) {
  const std::size_t count = entries.size();
  std::string names, centers;
  for (const Entry& e : entries) {
    names += e.name;
    if (e.flags & kEntryCenterName) centers += e.center;
  }
  std::vector<std::uint8_t> out(kEntriesHeaderBytes + kEntryBytes * count + names.size() + centers.size());
  putU32(out, 0, static_cast<std::uint32_t>(count));
  putU32(out, 4, static_cast<std::uint32_t>(names.size()));
  putU32(out, 8, static_cast<std::uint32_t>(centers.size()));
  std::uint32_t name_end = 0, center_end = 0;
  const std::size_t words_at = kEntriesHeaderBytes + 48 * count;
  for (std::size_t i = 0; i < count; ++i) {
    const Entry& e = entries[i];
    std::memcpy(&out[kEntriesHeaderBytes + 48 * i], e.values, 48);
    name_end += static_cast<std::uint32_t>(e.name.size());
    if (e.flags & kEntryCenterName) center_end += static_cast<std::uint32_t>(e.center.size());
    putU32(out, words_at + 4 * i, name_end);
    putU32(out, words_at + 4 * (count + i), center_end);
    putU32(out, words_at + 4 * (2 * count + i), e.flags);
  }
  std::memcpy(out.data() + kEntriesHeaderBytes + kEntryBytes * count, names.data(), names.size());
  std::memcpy(out.data() + kEntriesHeaderBytes + kEntryBytes * count + names.size(), centers.data(), centers.size());
  return out;
}

// A double as a JSON number token that reads back to it. -0 as "-0.0": "-0" is the integer 0
// (nlohmann), which is why the JS hands over JSON.stringify's +0 for a -0.
std::string number(double v) {
  if (v == 0 && std::signbit(v)) return "-0.0";
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

// The same entries as JSON text (names and centers here need no escaping).
std::string asText(const std::vector<Entry>& entries, const std::string& hash) {
  std::string text = R"({"version":1,"models":{")" + hash + R"(":{)";
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const Entry& e = entries[i];
    text += (i ? ",\"" : "\"") + e.name + "\":{";
    std::string fields;
    const auto add = [&](const std::string& field) { fields += (fields.empty() ? "" : ",") + field; };
    if (e.flags & kEntryStiffness) add("\"stiffness\":" + number(e.values[0]));
    if (e.flags & kEntryGravityPower) add("\"gravityPower\":" + number(e.values[1]));
    if (e.flags & kEntryDrag) add("\"drag\":" + number(e.values[2]));
    if (e.flags & kEntryGravityDir) {
      add("\"gravityDir\":[" + number(e.values[3]) + "," + number(e.values[4]) + "," + number(e.values[5]) + "]");
    }
    if (e.flags & kEntryCenter) add("\"center\":" + ((e.flags & kEntryCenterName) ? "\"" + e.center + "\"" : "null"));
    if (e.flags & kEntryIsRoot) add("\"isRoot\":true");
    text += fields + "}";
  }
  return text + "}}}";
}

bool read(const std::vector<std::uint8_t>& bytes, ModelEntry& out, std::vector<Warning>& warnings,
          const std::string& hash = "h") {
  return readSpringBonesEntries(bytes.data(), bytes.size(), hash, out, warnings);
}

// Refused, with nothing written: `out` empty, `warnings` as they were.
void expectRefused(const std::vector<std::uint8_t>& bytes, const char* why) {
  ModelEntry out;
  out.enabled = true;
  out.bones.emplace_back();
  std::vector<Warning> warnings{Warning{"earlier", "kept", "/"}};
  EXPECT_FALSE(read(bytes, out, warnings)) << why;
  EXPECT_FALSE(out.enabled) << why;
  EXPECT_TRUE(out.bones.empty()) << why;
  ASSERT_EQ(warnings.size(), 1u) << why;
  EXPECT_EQ(warnings[0].code, "earlier") << why;
}

void expectSameAsText(const std::vector<Entry>& entries, const char* why) {
  ModelEntry from_entries, from_text;
  std::vector<Warning> entry_warnings{Warning{"earlier", "kept", "/"}}, text_warnings{Warning{"earlier", "kept", "/"}};
  ASSERT_TRUE(read(encode(entries), from_entries, entry_warnings, "h")) << why;
  ASSERT_FALSE(parseSpringBonesText(asText(entries, "h"), "h", from_text, text_warnings)) << why;
  EXPECT_EQ(from_entries.enabled, from_text.enabled) << why;
  EXPECT_EQ(from_entries.path, from_text.path) << why;
  ASSERT_EQ(from_entries.bones.size(), from_text.bones.size()) << why;
  for (std::size_t i = 0; i < from_text.bones.size(); ++i) {
    const BoneEntry& a = from_entries.bones[i];
    const BoneEntry& b = from_text.bones[i];
    EXPECT_EQ(a.name, b.name) << why;
    EXPECT_EQ(from_entries.entryPath(a), from_text.entryPath(b)) << why;
    EXPECT_EQ(a.is_root, b.is_root) << why;
    EXPECT_EQ(a.has_center, b.has_center) << why;
    EXPECT_EQ(a.center, b.center) << why;
    // Bit for bit: the WebAssembly and native builds must agree, and so must the two readers.
    EXPECT_EQ(std::memcmp(&a.params, &b.params, sizeof a.params), 0) << why << " " << a.name;
  }
  ASSERT_EQ(entry_warnings.size(), text_warnings.size()) << why;
  for (std::size_t i = 0; i < text_warnings.size(); ++i) {
    EXPECT_EQ(entry_warnings[i].code, text_warnings[i].code) << why;
    EXPECT_EQ(entry_warnings[i].message, text_warnings[i].message) << why;
    EXPECT_EQ(entry_warnings[i].path, text_warnings[i].path) << why;
  }
}

std::vector<Entry> sample() {
  std::vector<Entry> entries(4);
  entries[0].name = "springbone_b";
  entries[0].flags |= kEntryIsRoot | kEntryCenter | kEntryCenterName;
  entries[0].center = "root";
  entries[1].name = "springbone_a";
  entries[1].flags = kEntryGravityPower | kEntryCenter;  // three params missing, world-space center
  entries[1].values[1] = 2;
  entries[2].name = "springbone_\xc3\xa9/~x";  // UTF-8 and JSON-pointer escapes in the path
  entries[2].flags = kEntryGravityDir | kEntryCenter | kEntryCenterName;
  entries[2].values[3] = 1e-5, entries[2].values[4] = -10, entries[2].values[5] = 3;
  entries[2].center = "";
  entries[3].name = "10";
  entries[3].flags = 0;
  return entries;
}

TEST(SpringBonesEntries, SameEntriesAndWarningsAsTheText) {
  expectSameAsText(sample(), "sample");
  expectSameAsText({}, "empty model");
  std::vector<Entry> many;
  for (int c = 0; c < 300; ++c) {
    for (int j = 0; j < 5; ++j) {
      Entry e;
      e.name = "springbone_" + std::to_string(c) + "_" + std::to_string(j);
      e.values[0] = 0.001 * (c + j);
      e.values[3] = 0.1 * j, e.values[5] = -0.03 * c;  // within [-10, 10]
      if (j == 0) e.flags |= kEntryIsRoot;
      many.push_back(e);
    }
  }
  expectSameAsText(many, "1500 entries");
  // Runs of one gravityDir (remembered between entries) broken by others, -0 apart from 0.
  const double dirs[][3] = {{0, -1, 0}, {0, -1, 0}, {-0.0, -1, 0}, {0, -1, -0.0}, {0, -1, 0}, {3, 4, 1.2},
                            {3, 4, 1.2}, {1e-5, 0, 0}, {0, -1, 0}};
  std::vector<Entry> runs;
  for (const auto& dir : dirs) {
    Entry e;
    e.name = "springbone_" + std::to_string(runs.size());
    std::memcpy(&e.values[3], dir, sizeof dir);
    runs.push_back(e);
  }
  expectSameAsText(runs, "runs of gravityDirs");
  std::vector<Entry> bounds(1);
  bounds[0].name = "springbone_bounds";
  for (double stiffness : {0.0, 4.0}) {
    bounds[0].values[0] = stiffness;
    bounds[0].values[1] = 2.0;
    bounds[0].values[2] = 1.0;
    expectSameAsText(bounds, "range bounds");
  }
}

TEST(SpringBonesEntries, RefusesWhatTheTextReadersWarnAbout) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const struct {
    int index;
    double value;
    const char* why;
  } cases[] = {{0, 4.0000001, "stiffness above 4"}, {0, -1e-300, "stiffness below 0"}, {0, nan, "stiffness NaN"},
               {1, 2.5, "gravityPower above 2"},    {2, 1.5, "drag above 1"},          {2, -inf, "drag -infinity"},
               {3, 10.5, "gravityDir x beyond 10"}, {4, inf, "gravityDir y infinite"}, {5, nan, "gravityDir z NaN"}};
  for (const auto& c : cases) {
    std::vector<Entry> entries = sample();
    entries[0].values[c.index] = c.value;
    expectRefused(encode(entries), c.why);
  }
  std::vector<Entry> zero = sample();
  zero[0].values[3] = zero[0].values[4] = zero[0].values[5] = 0;
  expectRefused(encode(zero), "gravityDir without a direction");
  zero[1].values[3] = zero[1].values[4] = zero[1].values[5] = 0;
  expectRefused(encode(zero), "the same gravityDir without a direction twice");
  std::vector<Entry> after_good = sample();  // entry 0 has [0,-1,0]; entry 1 a zero one after it
  after_good[1].flags |= kEntryGravityDir;
  after_good[1].values[3] = after_good[1].values[4] = after_good[1].values[5] = 0;
  expectRefused(encode(after_good), "a gravityDir without a direction after one with");
  std::vector<Entry> repeated = sample();
  repeated[1].name = repeated[0].name;
  expectRefused(encode(repeated), "a repeated name (the text reader keeps the last)");
  // Strings no JSON text holds: malformed UTF-8 in a name or a center, and a well-formed
  // sequence split across two names (the names section alone would pass).
  for (const char* bad : {"springbone_\xff", "springbone_\xc3", "springbone_\xed\xa0\x80", "\xc0\xaf"}) {
    std::vector<Entry> name = sample();
    name[1].name = bad;
    expectRefused(encode(name), "a name that is not UTF-8");
    std::vector<Entry> center = sample();
    center[0].center = bad;
    expectRefused(encode(center), "a center that is not UTF-8");
  }
  std::vector<Entry> split = sample();
  split[0].name = "springbone_\xc3";
  split[1].name = "\xa9springbone_a";
  expectRefused(encode(split), "a UTF-8 sequence split across two names");
  // A value out of range but its flag clear: not read, so not refused.
  std::vector<Entry> unread = sample();
  unread[1].values[0] = nan;
  ModelEntry out;
  std::vector<Warning> warnings;
  EXPECT_TRUE(read(encode(unread), out, warnings));
}

TEST(SpringBonesEntries, RefusesLayoutsThatDoNotAddUp) {
  const std::vector<std::uint8_t> good = encode(sample());
  const std::size_t count = 4;
  const std::size_t words_at = kEntriesHeaderBytes + 48 * count;
  ModelEntry out;
  std::vector<Warning> warnings;
  ASSERT_TRUE(read(good, out, warnings));

  for (std::size_t size : {std::size_t{0}, std::size_t{3}, kEntriesHeaderBytes - 1, good.size() - 1}) {
    expectRefused(std::vector<std::uint8_t>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(size)),
                  "truncated");
  }
  std::vector<std::uint8_t> longer = good;
  longer.push_back('x');
  expectRefused(longer, "a byte too many");

  const auto with = [&](std::size_t at, std::uint32_t value) {
    std::vector<std::uint8_t> bytes = good;
    putU32(bytes, at, value);
    return bytes;
  };
  expectRefused(with(12, 1), "the header's reserved word set");
  expectRefused(with(0, 5), "one entry more than the bytes hold");
  expectRefused(with(0, 3), "one entry less");
  // Counts and sizes whose sum wraps around 32 bits (size_t in WebAssembly) to the real size.
  expectRefused(with(0, static_cast<std::uint32_t>(count + (std::uint64_t{1} << 32) / kEntryBytes + 1)),
                "a count that overflows");
  expectRefused(with(0, 0xffffffffu), "the largest count");
  {
    std::vector<std::uint8_t> bytes = good;
    std::uint32_t name_bytes;
    std::memcpy(&name_bytes, &bytes[4], 4);
    putU32(bytes, 4, name_bytes + 0x80000000u);
    putU32(bytes, 8, 4 + 0x80000000u);  // together exactly 2^32 more than the real sizes (4: "root")
    expectRefused(bytes, "section sizes that wrap around");
  }
  expectRefused(with(4, 0xffffffffu), "a names section larger than the input");

  std::uint32_t name_end0;
  std::memcpy(&name_end0, &good[words_at], 4);
  expectRefused(with(words_at + 4, name_end0 - 1), "a name ending before the previous one");
  expectRefused(with(words_at, 0xffffffffu), "a name ending past its section");
  std::uint32_t last_name_end;  // the last name is "10": one byte shorter still follows the others
  std::memcpy(&last_name_end, &good[words_at + 4 * (count - 1)], 4);
  expectRefused(with(words_at + 4 * (count - 1), last_name_end - 1), "names not closing their section");
  expectRefused(with(words_at + 4 * count, 0xffffffffu), "a center ending past its section");
  expectRefused(with(words_at + 4 * (2 * count - 1), 0), "a center ending before the previous one");
  {
    // The center bytes of the second entry given to the first, which has no center name.
    std::vector<Entry> two(2);
    two[0].name = "springbone_a";
    two[1].name = "springbone_b";
    two[1].flags |= kEntryCenter | kEntryCenterName;
    two[1].center = "root";
    std::vector<std::uint8_t> bytes = encode(two);
    ModelEntry ok;
    std::vector<Warning> ok_warnings;
    ASSERT_TRUE(read(bytes, ok, ok_warnings));
    putU32(bytes, kEntriesHeaderBytes + 48 * 2 + 4 * 2, 4);
    expectRefused(bytes, "center bytes on an entry without a center name");
  }
  expectRefused(with(words_at + 4 * (2 * count + 1), kEntryCenterName), "a center name without a center");
  expectRefused(with(words_at + 4 * (2 * count + 3), 128), "an unknown flag");
}

TEST(SpringBonesEntries, AppendsToTheWarningsItIsGiven) {
  ModelEntry out;
  std::vector<Warning> warnings{Warning{"earlier", "kept", "/"}};
  ASSERT_TRUE(read(encode(sample()), out, warnings));
  EXPECT_TRUE(out.enabled);
  ASSERT_GT(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].code, "earlier");
  EXPECT_EQ(warnings[1].code, "param-missing");
}

}  // namespace
}  // namespace springbones
