// appendShortestFloat and shortestFloatValue (src/float_text.h) against their reference, printf
// "%.{6..9}g" + strtof: the text written must parse to the very double the reference returns,
// and shortestFloatValue must return that double, for every float we try: the exact-arithmetic range [1e-7, 1e7) densely, its edges, powers of two and ten, ties.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>

#include "float_text.h"

namespace springbones {
namespace {

std::string check(float v) {
  std::string text;
  appendShortestFloat(text, v);
  const double expected = shortestFloatDouble(v);
  const double got = std::strtod(text.c_str(), nullptr);
  if (std::memcmp(&expected, &got, sizeof got) != 0) {
    char line[160];
    std::snprintf(line, sizeof line, "%.9g: wrote %s, reference %.17g", static_cast<double>(v), text.c_str(), expected);
    return line;
  }
  const double value = shortestFloatValue(v);
  if (std::memcmp(&expected, &value, sizeof value) != 0) {
    char line[160];
    std::snprintf(line, sizeof line, "%.9g: value %.17g, reference %.17g", static_cast<double>(v), value, expected);
    return line;
  }
  return {};
}

float fromBits(std::uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

TEST(FloatText, MatchesPrintfOnEdgesAndRoundNumbers) {
  for (float v : {0.4f, 0.1f, 0.3f, 0.5f, 1.0f, 2.0f, 0.05f, 1e-7f, 9.9999999e6f, 1e7f, 0.0f, -0.0f, 1234567.5f,
                  8388608.0f, 16777215.0f, 3.4028235e38f, 1.17549435e-38f, 1.4e-45f, -0.6f, 9.9999995f, 0.99999994f}) {
    EXPECT_EQ(check(v), "");
  }
  for (int k = -30; k <= 30; ++k) {
    EXPECT_EQ(check(std::ldexp(1.0f, k)), "");
    EXPECT_EQ(check(static_cast<float>(std::pow(10.0, k / 4))), "");
    EXPECT_EQ(check(std::nextafter(static_cast<float>(std::pow(10.0, k / 4)), 0.0f)), "");
  }
  std::string text;
  appendShortestFloat(text, std::nanf(""));
  EXPECT_EQ(text, "null");
}

TEST(FloatText, MatchesPrintfOnManyFloats) {
  std::mt19937 rng(7);
  int failures = 0;
  // Uniform over the bit patterns of [1e-8, 1e8] (both signs), so every binade is covered.
  const std::uint32_t lo = 0x322bcc77u;  // ~1e-8
  const std::uint32_t hi = 0x4cbebc20u;  // 1e8
  for (int i = 0; i < 300000 && failures < 10; ++i) {
    float v = fromBits(lo + static_cast<std::uint32_t>(rng() % (hi - lo)));
    if (rng() & 1) v = -v;
    const std::string f = check(v);
    if (!f.empty()) {
      ADD_FAILURE() << f;
      ++failures;
    }
  }
  // Short decimals, the values metadata holds (0.35, 1.5, 0.05...).
  for (int n = -20000; n <= 20000 && failures < 10; ++n) {
    for (float scale : {1e-4f, 1e-2f, 1.0f}) {
      const std::string f = check(static_cast<float>(n) * scale);
      if (!f.empty()) {
        ADD_FAILURE() << f;
        ++failures;
      }
    }
  }
}

}  // namespace
}  // namespace springbones
