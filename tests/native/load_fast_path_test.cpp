// The loader's own arithmetic against glm: linkHierarchy (glb_loader.cpp) multiplies the rest
// matrices with its own scalar code, which must give glm's product bit for bit.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "springbones.h"
#include "test_helpers.h"
#include "transform_math.h"

namespace springbones {
namespace {

bool sameBits(const void* a, const void* b, std::size_t n) { return std::memcmp(a, b, n) == 0; }

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
