// springbones_load_report: how long loading a wearable takes natively, stage by stage.
//
// Not a test: it prints numbers for the load targets. Usage:
//   springbones_load_report [chains] [joints per chain] [runs]      (default 1000 5 9)
// The wearable is the one scripts/benchmarks/bench.mjs builds (wearableGltf): node 0 "root"; per chain a
// parent "chain_c" and joints "springbone_c_j" each 0.05 below the previous, then an end node; a
// springBones entry for every joint (stiffness 1, gravityPower 0.5, drag 0.4, the first isRoot).
// 1000 x 5 is 7,001 nodes and 5,000 joints; 20000 x 5 is 140,001 nodes and 100,000 joints.
//
// Each run does what the WebAssembly loadRig does (wasm/bindings.cpp) with the hash given:
// loadSkeleton, parseSpringBonesText, buildRig. Printed: the median over the runs (after one
// warm-up) of each stage and of the whole, in ms. Build it optimised (native-release).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "springbones/readers.h"
#include "springbones/springbones.h"

namespace {

using namespace springbones;
using Clock = std::chrono::steady_clock;

// Written by hand rather than through nlohmann so the text looks like JSON.stringify's
// (no spaces, shortest numbers), the input the JavaScript API hands the core.
std::string number(double v) {
  char text[32];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(text, sizeof text, "%.*g", precision, v);
    if (std::strtod(text, nullptr) == v) break;
  }
  return text;
}

struct Wearable {
  std::string gltf;
  std::string springBones;
  std::size_t nodes = 0;
};

Wearable makeWearable(int chains, int joints) {
  Wearable w;
  std::vector<std::string> nodes;
  std::vector<std::vector<int>> children(1);
  nodes.push_back(R"("name":"root")");
  std::string entries;
  const std::string params = R"("stiffness":1,"gravityPower":0.5,"gravityDir":[0,-1,0],"drag":0.4)";
  for (int c = 0; c < chains; ++c) {
    const int parent = static_cast<int>(nodes.size());
    children[0].push_back(parent);
    nodes.push_back("\"name\":\"chain_" + std::to_string(c) + "\",\"translation\":[" + number(c * 0.1) + ",1,0]");
    children.emplace_back();
    int prev = parent;
    for (int j = 0; j <= joints; ++j) {
      const int index = static_cast<int>(nodes.size());
      children[prev].push_back(index);
      const std::string name =
          j < joints ? "springbone_" + std::to_string(c) + "_" + std::to_string(j) : "end_" + std::to_string(c);
      nodes.push_back("\"name\":\"" + name + "\",\"translation\":" + (j == 0 ? "[0,0,0]" : "[0,-0.05,0]"));
      children.emplace_back();
      if (j < joints) {
        entries +=
            (entries.empty() ? "" : ",") + ("\"" + name + "\":{" + params) + (j == 0 ? ",\"isRoot\":true}" : "}");
      }
      prev = index;
    }
  }
  w.gltf = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[)";
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    w.gltf += (i ? ",{" : "{") + nodes[i];
    if (!children[i].empty()) {
      w.gltf += ",\"children\":[";
      for (std::size_t k = 0; k < children[i].size(); ++k) {
        w.gltf += (k ? "," : "") + std::to_string(children[i][k]);
      }
      w.gltf += "]";
    }
    w.gltf += "}";
  }
  w.gltf += "]}";
  w.springBones = R"({"version":1,"models":{"bench":{)" + entries + "}}}";
  w.nodes = nodes.size();
  return w;
}

double ms(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const int chains = argc > 1 ? std::atoi(argv[1]) : 1000;
  const int joints = argc > 2 ? std::atoi(argv[2]) : 5;
  const int runs = argc > 3 ? std::max(1, std::atoi(argv[3])) : 9;
  if (chains < 1 || joints < 1) {
    std::fprintf(stderr, "usage: springbones_load_report [chains >= 1] [joints >= 1] [runs]\n");
    return 2;
  }
  const Wearable w = makeWearable(chains, joints);
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(w.gltf.data());

  std::vector<double> skeleton_ms, metadata_ms, build_ms, total_ms;
  std::size_t joint_count = 0, warning_count = 0;
  for (int r = 0; r <= runs; ++r) {
    const auto t0 = Clock::now();
    Skeleton skeleton;
    if (Error e = loadSkeleton(bytes, w.gltf.size(), skeleton)) {
      std::fprintf(stderr, "loadSkeleton failed: %s\n", e.message.c_str());
      return 1;
    }
    const auto t1 = Clock::now();
    ModelEntry model;
    std::vector<Warning> warnings;
    if (Error e = parseSpringBonesText(w.springBones, "bench", model, warnings)) {
      std::fprintf(stderr, "parseSpringBonesText failed: %s\n", e.message.c_str());
      return 1;
    }
    const auto t2 = Clock::now();
    auto rig = buildRig(std::move(skeleton), model, std::move(warnings));
    const auto t3 = Clock::now();
    joint_count = rig->joints.size();
    warning_count = rig->warnings.size();
    rig.reset();
    if (r == 0) continue;  // warm-up
    skeleton_ms.push_back(ms(t0, t1));
    metadata_ms.push_back(ms(t1, t2));
    build_ms.push_back(ms(t2, t3));
    total_ms.push_back(ms(t0, t3));
  }
  std::printf("wearable: %zu nodes (%zu KB glTF JSON), %zu joints, %zu warnings, springBones %zu KB\n", w.nodes,
              w.gltf.size() / 1024, joint_count, warning_count, w.springBones.size() / 1024);
  std::printf(
      "median of %d warm loads, ms: loadSkeleton %.3f  parseSpringBonesText %.3f  buildRig %.3f  "
      "total %.3f\n",
      runs, median(skeleton_ms), median(metadata_ms), median(build_ms), median(total_ms));
  return 0;
}
