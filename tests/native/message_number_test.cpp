// A message's numbers and cuts as native code writes them (common/message_number.h); the runtime
// module's placeholders are held to these by tests/wasm/message_numbers.test.mjs.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "common/message_number.h"
#include "common/quoted_value.h"
#include "common/typed_value.h"

namespace springbones {
namespace {

TEST(MessageNumber, WritesPrintfsConversions) {
  EXPECT_EQ(numberText(0.1f, NumberStyle::kG7), "0.1");
  EXPECT_EQ(numberText(1e30f, NumberStyle::kG7), "1e+30");
  EXPECT_EQ(numberText(1234565, NumberStyle::kG6), "1.23456e+06");  // ties to even
  EXPECT_EQ(numberText(0.1, NumberStyle::kG15), "0.1");
  EXPECT_EQ(numberText(1.5f, NumberStyle::kFixed), "1.500000");
  EXPECT_EQ(numberText(1.5f, NumberStyle::kFixedTrim), "1.5");
  EXPECT_EQ(numberText(100.0, NumberStyle::kFixedTrim), "100");
  EXPECT_EQ(numberText(-0.0, NumberStyle::kFixedTrim), "-0");
  EXPECT_EQ(numberText(std::numeric_limits<float>::infinity(), NumberStyle::kFixed), "inf");
}

TEST(MessageNumber, CutsAtABytePrefixWithUFFFDForEachByteOfACutCharacter) {
  std::string out;
  appendCut(out, "abcdefgh", 8);
  EXPECT_EQ(out, "abcdefgh");
  out.clear();
  appendCut(out, "abcdefghi", 8);
  EXPECT_EQ(out, "abcde...");
  out.clear();
  // "\xE2\x82\xAC" (the euro sign) cut after two of its bytes: two U+FFFD.
  appendCut(out,
            "abc\xE2\x82\xAC"
            "defgh",
            8);
  EXPECT_EQ(out, "abc\xEF\xBF\xBD\xEF\xBF\xBD...");
  out.clear();
  appendCut(out,
            "abcd\xE2\x82\xAC"
            "defgh",
            10);
  EXPECT_EQ(out, "abcd\xE2\x82\xAC...");
}

TEST(MessageNumber, QuotesAValueCutToItsLength) {
  TypedWriter writer;
  writer.array(3);
  writer.number(0.1);
  writer.string(std::string(70, 'x'));
  writer.number(2);
  TypedDocument doc;
  ASSERT_FALSE(doc.decode(writer.bytes().data(), writer.bytes().size(), 1024));
  EXPECT_EQ(quoteValue(doc.root(), 20), "[0.1,\"xxxxxxxxxxx...");
  EXPECT_EQ(quoteValue(doc.root(), 200), "[0.1,\"" + std::string(70, 'x') + "\",2]");
}

}  // namespace
}  // namespace springbones
