// dump_rotations: runs a scripted scenario in the native build and writes, for every frame, the
// driver matrices it fed in and the rotations that came out, as JSON lines. The WebAssembly
// parity test (tests/wasm/parity.test.mjs) runs the same scenario through the JS API and compares
// (native and WASM builds agree within 1e-6: docs/design.md, Numbers we hold ourselves to).
//
//   dump_rotations <glb> <springBones.json | -> <hash | -> <frames> <fps>
//                  [--drive rest|sway] [--step-hz H] [--max-substeps N] [--out FILE]
//                  [--wind STRENGTH,GUSTS,SEED] [--body-colliders]
//
// "-" for the metadata means none; "-" for the hash means the GLB's own content hash. Frame k
// (1..frames) sets the drivers for time k / fps and steps by 1 / fps. --drive sway is the motion
// of bin/sway.mjs, written out below with the same operations in the same order (keep the
// two in step); --drive rest (the default) leaves the drivers at their rest world matrices.
// Floats are printed with 9 significant digits, which reads back as the same float.
// --vrm reads the file as a VRM avatar (loadVrm; the metadata and hash arguments are ignored).
// --hash prints one line instead, {"frames", "joints", "hash"}: FNV-1a 64 over the bytes
// (little-endian) of every frame's rotations, as tests/scenarios/frame_hash.mjs computes it in
// Node and in Chromium.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "springbones/content_hash.h"
#include "springbones/readers.h"
#include "springbones/springbones.h"
#include "springbones/vrm.h"

namespace {

using namespace springbones;

constexpr double kPi = 3.141592653589793;

// bin/sway.mjs sine(): Bhaskara I's approximation of sin, correctly rounded operations only.
double sine(double x) {
  const double two_pi = 2 * kPi;
  double r = x - two_pi * std::floor(x / two_pi);
  double sign = 1;
  if (r >= kPi) {
    r = r - kPi;
    sign = -1;
  }
  const double p = r * (kPi - r);
  return (sign * (16 * p)) / (5 * kPi * kPi - 4 * p);
}

// bin/sway.mjs swayTransform().
void swayTransform(double t, double out[16]) {
  const double u = 0.2 * sine(2 * kPi * 0.7 * t);
  const double v = 0.15 * sine(2 * kPi * 1.3 * t + 1);
  const double n = std::sqrt(1 + u * u + v * v);
  const double x = 0;
  const double y = u / n;
  const double z = v / n;
  const double w = 1 / n;
  out[0] = 1 - 2 * (y * y + z * z);
  out[1] = 2 * (x * y + z * w);
  out[2] = 2 * (x * z - y * w);
  out[3] = 0;
  out[4] = 2 * (x * y - z * w);
  out[5] = 1 - 2 * (x * x + z * z);
  out[6] = 2 * (y * z + x * w);
  out[7] = 0;
  out[8] = 2 * (x * z + y * w);
  out[9] = 2 * (y * z - x * w);
  out[10] = 1 - 2 * (x * x + y * y);
  out[11] = 0;
  out[12] = 0.08 * sine(2 * kPi * 0.9 * t);
  out[13] = 0.02 * sine(2 * kPi * 2.1 * t);
  out[14] = 0.05 * sine(2 * kPi * 0.5 * t + 2);
  out[15] = 1;
}

// bin/sway.mjs swayDrivers().
void swayDrivers(const std::vector<float>& rest, float* out, double t) {
  double s[16];
  swayTransform(t, s);
  for (std::size_t base = 0; base < rest.size(); base += 16) {
    for (int c = 0; c < 4; ++c) {
      const double m0 = rest[base + 4 * c];
      const double m1 = rest[base + 4 * c + 1];
      const double m2 = rest[base + 4 * c + 2];
      const double m3 = rest[base + 4 * c + 3];
      for (int r = 0; r < 4; ++r) {
        out[base + 4 * c + r] = static_cast<float>(s[r] * m0 + s[4 + r] * m1 + s[8 + r] * m2 + s[12 + r] * m3);
      }
    }
  }
}

bool readFile(const std::string& path, std::string& out) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return false;
  out.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  return true;
}

void writeFloats(std::FILE* out, const float* values, std::size_t count) {
  std::fputc('[', out);
  for (std::size_t i = 0; i < count; ++i) { std::fprintf(out, i ? ",%.9g" : "%.9g", static_cast<double>(values[i])); }
  std::fputc(']', out);
}

int usage() {
  std::fprintf(stderr,
               "usage: dump_rotations <glb> <springBones.json|-> <hash|-> <frames> <fps>\n"
               "                      [--drive rest|sway] [--step-hz H] [--max-substeps N] [--out FILE]\n"
               "                      [--vrm] [--hash] [--wind STRENGTH,GUSTS,SEED] [--body-colliders]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 6) return usage();
  const std::string glb_path = argv[1], metadata_path = argv[2], hash_arg = argv[3];
  const int frames = std::atoi(argv[4]);
  const double fps = std::atof(argv[5]);
  std::string drive = "rest", out_path;
  InstanceOptions options;
  bool vrm = false, hash_only = false;
  bool wind_on = false;
  Wind wind;
  RigOptions rig_options;
  for (int i = 6; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--vrm" || flag == "--hash") {
      (flag == "--vrm" ? vrm : hash_only) = true;
      continue;
    }
    if (flag == "--body-colliders") {  // loadRig's colliders: 'dcl-body', hitRadius 0.01
      rig_options.preset = ColliderPreset::kDclBody;
      rig_options.hit_radius = 0.01f;
      continue;
    }
    if (i + 1 >= argc) return usage();
    const std::string value = argv[++i];
    if (flag == "--drive") {
      drive = value;
    } else if (flag == "--step-hz") {
      options.step_hz = std::atof(value.c_str());
    } else if (flag == "--max-substeps") {
      options.max_substeps = std::atoi(value.c_str());
    } else if (flag == "--out") {
      out_path = value;
    } else if (flag == "--wind") {  // from direction (1, 0, 0.5), as tests/wasm/parity.test.mjs sets it
      unsigned seed = 0;
      if (std::sscanf(value.c_str(), "%f,%f,%u", &wind.strength, &wind.gust_frequency, &seed) != 3) return usage();
      wind.direction = Vec3{1.0f, 0.0f, 0.5f};
      wind.seed = seed;
      wind_on = true;
    } else {
      return usage();
    }
  }
  if (frames < 0 || !(fps > 0) || (drive != "rest" && drive != "sway")) return usage();

  std::string glb, metadata = "null";
  if (!readFile(glb_path, glb)) {
    std::fprintf(stderr, "dump_rotations: cannot read %s\n", glb_path.c_str());
    return 1;
  }
  if (metadata_path != "-" && !readFile(metadata_path, metadata)) {
    std::fprintf(stderr, "dump_rotations: cannot read %s\n", metadata_path.c_str());
    return 1;
  }
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(glb.data());
  std::shared_ptr<const Rig> rig;
  if (vrm) {
    if (Error e = loadVrm(bytes, glb.size(), rig)) {
      std::fprintf(stderr, "dump_rotations: %s: %s\n", errorCodeName(e.code), e.message.c_str());
      return 1;
    }
  } else {
    Skeleton skeleton;
    if (Error e = loadSkeleton(bytes, glb.size(), skeleton)) {
      std::fprintf(stderr, "dump_rotations: %s: %s\n", errorCodeName(e.code), e.message.c_str());
      return 1;
    }
    const std::string hash = hash_arg == "-" ? contentHash(bytes, glb.size()) : hash_arg;
    ModelEntry model;
    std::vector<Warning> warnings;
    if (Error e = parseSpringBonesText(metadata, hash, model, warnings)) {
      std::fprintf(stderr, "dump_rotations: %s: %s\n", errorCodeName(e.code), e.message.c_str());
      return 1;
    }
    rig = buildRig(std::move(skeleton), model, std::move(warnings), rig_options);
  }
  Instance instance(rig, options);
  if (wind_on) instance.setWind(wind);

  std::FILE* out = out_path.empty() ? stdout : std::fopen(out_path.c_str(), "w");
  if (out == nullptr) {
    std::fprintf(stderr, "dump_rotations: cannot write %s\n", out_path.c_str());
    return 1;
  }
  const std::size_t driver_floats = 16 * instance.driverCount();
  const std::vector<float> rest(instance.driverMatrices(), instance.driverMatrices() + driver_floats);
  const double dt = 1 / fps;
  std::uint64_t fnv = 14695981039346656037ull;  // FNV-1a 64 offset basis
  for (int k = 1; k <= frames; ++k) {
    if (drive == "sway") swayDrivers(rest, instance.driverMatrices(), k / fps);
    instance.step(dt);
    if (hash_only) {
      const float* rotations = instance.rotations();
      for (std::size_t i = 0; i < 4 * instance.jointCount(); ++i) {
        std::uint32_t bits;
        std::memcpy(&bits, &rotations[i], sizeof bits);
        for (int b = 0; b < 4; ++b) {
          fnv = (fnv ^ ((bits >> (8 * b)) & 0xffu)) * 1099511628211ull;  // FNV-1a 64 prime
        }
      }
      continue;
    }
    std::fprintf(out, "{\"frame\":%d,\"drivers\":", k);
    writeFloats(out, instance.driverMatrices(), driver_floats);
    std::fputs(",\"rotations\":", out);
    writeFloats(out, instance.rotations(), 4 * instance.jointCount());
    std::fputs("}\n", out);
  }
  if (hash_only) {
    std::fprintf(out, "{\"frames\":%d,\"joints\":%zu,\"hash\":\"%016llx\"}\n", frames, instance.jointCount(),
                 static_cast<unsigned long long>(fnv));
  }
  const bool ok = std::ferror(out) == 0;
  if (out != stdout) std::fclose(out);
  return ok ? 0 : 1;
}
