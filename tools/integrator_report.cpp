// springbones_integrator_report: the stability comparison of the two integrators (bone length
// drift, explosions, collider response, cost), on our own runs; docs/xpbd.md shows a run and
// reads it.
//
// Not a test: it prints a table and writes JSON, for docs/xpbd.md and for tracking. Usage:
//   springbones_integrator_report [out.json]      (default: integrator_report.json)
// Build it optimised (native-release) before reading the cost columns.
//
// What runs: two rigs (a 100-joint head of hair, 20 chains of 5, leaning on a head sphere
// collider; a 10-joint tail), two parameter sets (aggressive: stiffness 4, drag 0, gravityPower
// 2, the energetic end of every range; typical: 1, 0.4, 0.5), two frame patterns (30 fps with a
// 0.5 s frame every 2 s; steady 60 fps), 120 s of rapid head shaking (the extreme
// motion XPBD designs are tuned with), each under
//   vrm:  springbones::Instance as shipped (60 Hz fixed steps, at most 4 per frame);
//   xpbd: Instance with integrator kXpbd at its defaults: 120 Hz, 4 iterations, at most 8
//         substeps per frame (the same 1/15 s simulated per frame at most).
// Stability columns:
//   length err max / final: worst |tail - head| / rest - 1 over every joint and frame, and on the
//     last frame, measured through the output world matrices (bone length drift);
//   explosions: frames with a non-finite or non-unit rotation or a length error above 1%;
//   penetration: deepest tail inside the head collider (radius + hit radius), mm (collision
//     response);
//   swing m/s: speed of the tails relative to their heads (mean, max), the energy kept;
// then the cost (time inside step(), best of 7 runs of 600 frames at 60 fps: us per frame and ns
// per joint per (sub)step), and how close the xpbd pose stays to the default's while walking
// (angle between the bones' world rotations on the same frame).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "springbones/readers.h"
#include "springbones/springbones.h"

namespace {

using namespace springbones;
using nlohmann::json;

constexpr double kSeconds = 120.0;
constexpr float kHeadRadius = 0.08f;
constexpr float kHitRadius = 0.01f;

struct ParamSet {
  const char* name;
  double stiffness, drag, gravity;
};

struct FramePattern {
  const char* name;
  double frame, spike, spike_every;  // seconds; spike_every 0: no spikes
};

json node(const std::string& name, glm::vec3 t, std::vector<int> children = {}) {
  json n = {{"name", name}, {"translation", {t.x, t.y, t.z}}};
  if (!children.empty()) n["children"] = children;
  return n;
}

json rootEntry(const ParamSet& p) {
  return {{"isRoot", true},
          {"stiffness", p.stiffness},
          {"drag", p.drag},
          {"gravityPower", p.gravity},
          {"gravityDir", {0, -1, 0}}};
}

std::shared_ptr<const Rig> buildFromJson(const json& nodes, const json& bones, const RigOptions& options) {
  const std::string gltf = json{{"asset", {{"version", "2.0"}}}, {"nodes", nodes}}.dump();
  Skeleton skeleton;
  if (Error e = loadSkeleton(reinterpret_cast<const std::uint8_t*>(gltf.data()), gltf.size(), skeleton)) {
    std::fprintf(stderr, "rig: %s\n", e.message.c_str());
    std::exit(1);
  }
  ModelEntry model;
  std::vector<Warning> warnings;
  parseSpringBonesText(json{{"version", 1}, {"models", {{"h", bones}}}}.dump(), "h", model, warnings);
  return buildRig(std::move(skeleton), model, warnings, options);
}

// 20 chains of 5 joints (0.05 m bones) around the top of a head sphere, leaning out and down.
std::shared_ptr<const Rig> hairRig(const ParamSet& p) {
  json nodes = json::array({node("Avatar_Head", {0, 0, 0})});
  json bones = json::object();
  std::vector<int> roots;
  for (int c = 0; c < 20; ++c) {
    const float a = static_cast<float>(c * 2.0 * M_PI / 20);
    const glm::vec3 out(std::cos(a), 0, std::sin(a));
    const glm::vec3 bone = 0.05f * glm::normalize(0.6f * out + glm::vec3(0, -1, 0));
    for (int j = 0; j <= 5; ++j) {
      const int index = static_cast<int>(nodes.size());
      const std::string name = "springbone_hair" + std::to_string(c) + (j < 5 ? "_" + std::to_string(j) : "_tip");
      const glm::vec3 t = j == 0 ? 0.092f * out + glm::vec3(0, 0.02f, 0) : bone;
      nodes.push_back(node(name, t, j < 5 ? std::vector<int>{index + 1} : std::vector<int>{}));
      if (j == 0) {
        roots.push_back(index);
        bones[name] = rootEntry(p);
      }
    }
  }
  nodes[0]["children"] = roots;
  RigOptions options;
  ColliderSpec head;
  head.node = "Avatar_Head";
  head.radius = kHeadRadius;
  options.colliders = {head};
  options.hit_radius = kHitRadius;
  return buildFromJson(nodes, bones, options);
}

// One chain of 10 joints (0.1 m bones) pointing back and a little down from the hips.
std::shared_ptr<const Rig> tailRig(const ParamSet& p) {
  json nodes = json::array({node("Avatar_Hips", {0, 0, 0}, {1})});
  for (int j = 0; j <= 10; ++j) {
    const std::string name = j < 10 ? "springbone_tail_" + std::to_string(j) : "springbone_tail_tip";
    const glm::vec3 t = j == 0 ? glm::vec3(0, 0, -0.1f) : glm::vec3(0, -0.02f, -0.098f);
    nodes.push_back(node(name, t, j < 10 ? std::vector<int>{j + 2} : std::vector<int>{}));
  }
  return buildFromJson(nodes, json{{"springbone_tail_0", rootEntry(p)}}, RigOptions{});
}

// Rapid head shaking: +-1.2 rad about Y at 3 Hz, a nod of +-0.5 rad at 2 Hz, a sway of +-0.3 m.
glm::mat4 shaking(double t) {
  glm::mat4 m = glm::translate(glm::mat4(1), glm::vec3(0.3 * std::sin(2 * M_PI * 1.1 * t), 1.6, 0));
  m = glm::rotate(m, float(1.2 * std::sin(2 * M_PI * 3.0 * t)), glm::vec3(0, 1, 0));
  return glm::rotate(m, float(0.5 * std::sin(2 * M_PI * 2.0 * t)), glm::vec3(1, 0, 0));
}

// One integrator behind a common face: springbones::Instance with the integrator and the XPBD
// passes the row names ("xpbd-it2": 2 passes), at each integrator's default rate and substep cap.
class Runner {
 public:
  Runner(std::shared_ptr<const Rig> rig, const std::string& integrator)
      : instance_(std::move(rig), options(integrator)) {}
  void setDriver(std::size_t d, const glm::mat4& m) {
    std::memcpy(instance_.driverMatrices() + 16 * d, &m[0][0], sizeof(float) * 16);
  }
  void step(double dt) {
    instance_.step(dt);
    substeps_ += instance_.lastSteps();
  }
  const float* rotations() const { return instance_.rotations(); }
  glm::mat4 world(std::size_t joint) const {
    glm::mat4 m;
    std::memcpy(&m[0][0], instance_.worldMatrices() + 16 * joint, sizeof(float) * 16);
    return m;
  }
  long long substeps() const { return substeps_; }

 private:
  static InstanceOptions options(const std::string& integrator) {
    InstanceOptions o;
    if (integrator != "vrm") o.integrator = Integrator::kXpbd;
    if (integrator == "xpbd-it2") o.xpbd_iterations = 2;
    return o;
  }
  Instance instance_;
  long long substeps_ = 0;
};

// The joint's tail in its local space, for the glm arithmetic of this report.
glm::vec3 tailLocal(const Joint& joint) { return {joint.tail_local.x, joint.tail_local.y, joint.tail_local.z}; }

glm::quat rotationAt(const float* rotations, std::size_t j) {
  const float* r = rotations + 4 * j;
  return glm::quat(r[3], r[0], r[1], r[2]);
}

using Motion = glm::mat4 (*)(double);

// Walking at 1.2 m/s while turning at 0.5 rad/s, with a 2 cm bob and a slow look around.
glm::mat4 walking(double t) {
  glm::mat4 m = glm::rotate(glm::mat4(1), float(0.5 * t), glm::vec3(0, 1, 0));
  m = glm::translate(m, glm::vec3(0, 1.6 + 0.02 * std::sin(2 * M_PI * 2.0 * t), 1.2 * t));
  return glm::rotate(m, float(0.3 * std::sin(2 * M_PI * 0.5 * t)), glm::vec3(0, 1, 0));
}

std::unique_ptr<Runner> makeRunner(const std::string& integrator, std::shared_ptr<const Rig> rig) {
  return std::make_unique<Runner>(std::move(rig), integrator);
}

std::shared_ptr<const Rig> makeRigNamed(const std::string& name, const ParamSet& p) {
  return name == "hair100" ? hairRig(p) : tailRig(p);
}

// The frame times of a pattern, for `seconds` of animation.
std::vector<double> frameTimes(const FramePattern& pattern, double seconds) {
  std::vector<double> out;
  double t = 0, since_spike = 0;
  while (t < seconds) {
    double dt = pattern.frame;
    since_spike += dt;
    if (pattern.spike_every > 0 && since_spike >= pattern.spike_every) {
      dt = pattern.spike;
      since_spike = 0;
    }
    t += dt;
    out.push_back(dt);
  }
  return out;
}

struct Stability {
  std::string integrator, rig, params, frames;
  std::size_t joints = 0;
  long long frame_count = 0, substeps = 0, explosions = 0;
  double max_length_error = 0, final_length_error = 0, max_penetration = 0;
  double mean_swing_speed = 0, max_swing_speed = 0;  // m/s of the tails relative to their heads
};

// The stability comparison: rapid head shaking, every frame checked.
Stability runStability(const std::string& integrator, const std::string& rig_name, const ParamSet& params,
                       const FramePattern& pattern) {
  auto rig = makeRigNamed(rig_name, params);
  auto runner = makeRunner(integrator, rig);
  Stability r;
  r.integrator = integrator;
  r.rig = rig_name;
  r.params = params.name;
  r.frames = pattern.name;
  r.joints = rig->joints.size();
  const bool has_collider = !rig->colliders.empty();
  std::vector<glm::vec3> last_offset(rig->joints.size(), glm::vec3(0.0f));
  double t = 0, speed_sum = 0;
  long long speed_count = 0;
  for (double dt : frameTimes(pattern, kSeconds)) {
    t += dt;
    const glm::mat4 driver = shaking(t);
    const glm::vec3 sphere_center(driver[3]);
    for (std::size_t d = 0; d < rig->drivers.size(); ++d) runner->setDriver(d, driver);
    runner->step(dt);
    ++r.frame_count;
    bool exploded = false;
    double frame_worst = 0;
    for (std::size_t j = 0; j < rig->joints.size(); ++j) {
      const float norm = glm::length(rotationAt(runner->rotations(), j));
      if (!std::isfinite(norm) || std::fabs(norm - 1.0f) > 1e-3f) exploded = true;
      const glm::mat4 w = runner->world(j);
      const glm::vec3 head(w[3]);
      const glm::vec3 tail(w * glm::vec4(tailLocal(rig->joints[j]), 1.0f));
      const double error = std::fabs(glm::length(tail - head) / rig->joints[j].rest_length - 1.0);
      if (!(error <= 0.01)) exploded = true;  // NaN counts
      if (std::isfinite(error)) frame_worst = std::max(frame_worst, error);
      // How fast the bone swings (its tail relative to its head): a measure of the energy each
      // integrator keeps. Spike frames are left out: their dt is not the simulated time.
      if (r.frame_count > 1 && dt == pattern.frame) {
        const double speed = glm::length((tail - head) - last_offset[j]) / dt;
        if (std::isfinite(speed)) {
          speed_sum += speed;
          ++speed_count;
          r.max_swing_speed = std::max(r.max_swing_speed, speed);
        }
      }
      last_offset[j] = tail - head;
      if (has_collider) {
        const double inside = kHeadRadius + kHitRadius - glm::length(tail - sphere_center);
        if (std::isfinite(inside)) r.max_penetration = std::max(r.max_penetration, inside);
      }
    }
    r.max_length_error = std::max(r.max_length_error, frame_worst);
    r.final_length_error = frame_worst;
    if (exploded) ++r.explosions;
  }
  r.substeps = runner->substeps();
  r.mean_swing_speed = speed_count > 0 ? speed_sum / speed_count : 0;
  return r;
}

struct Cost {
  std::string integrator, rig;
  std::size_t joints = 0;
  double us_per_frame = 0, ns_per_joint_step = 0;
};

// Time inside step() only, steady 60 fps of rapid head shaking, typical parameters; the best of
// several runs, since the machine may be busy with other work.
Cost measureCost(const std::string& integrator, const std::string& rig_name) {
  constexpr int kRuns = 7;
  constexpr int kFrames = 600;
  const ParamSet typical{"typical", 1.0, 0.4, 0.5};
  auto rig = makeRigNamed(rig_name, typical);
  Cost c;
  c.integrator = integrator;
  c.rig = rig_name;
  c.joints = rig->joints.size();
  double best = 1e30;
  long long substeps = 0;
  for (int run = 0; run < kRuns; ++run) {
    auto runner = makeRunner(integrator, rig);
    double seconds = 0;
    for (int f = 1; f <= kFrames; ++f) {
      const glm::mat4 driver = shaking(f / 60.0);
      for (std::size_t d = 0; d < rig->drivers.size(); ++d) runner->setDriver(d, driver);
      const auto start = std::chrono::steady_clock::now();
      runner->step(1.0 / 60);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    if (seconds < best) {
      best = seconds;
      substeps = runner->substeps();
    }
  }
  c.us_per_frame = best * 1e6 / kFrames;
  c.ns_per_joint_step = best * 1e9 / (double(substeps) * c.joints);
  return c;
}

struct Agreement {
  std::string rig;
  double mean_deg = 0, max_first_2s_deg = 0, max_after_2s_deg = 0, final_mean_deg = 0;
};

// How far the xpbd pose is from the default's on the same frames: typical parameters, walking,
// 60 fps, 20 s. (Under rapid shaking the two diverge like any two chaotic trajectories, so that
// is not a useful comparison.)
Agreement compareWithVrm(const std::string& rig_name) {
  const ParamSet typical{"typical", 1.0, 0.4, 0.5};
  auto rig = makeRigNamed(rig_name, typical);
  auto vrm = makeRunner("vrm", rig);
  auto xpbd = makeRunner("xpbd", rig);
  Agreement a;
  a.rig = rig_name;
  double sum = 0;
  long long count = 0;
  const int frames = 60 * 20;
  for (int f = 1; f <= frames; ++f) {
    const glm::mat4 driver = walking(f / 60.0);
    for (Runner* r : {vrm.get(), xpbd.get()}) {
      for (std::size_t d = 0; d < rig->drivers.size(); ++d) r->setDriver(d, driver);
      r->step(1.0 / 60);
    }
    double frame_sum = 0;
    for (std::size_t j = 0; j < rig->joints.size(); ++j) {
      // The world rotation of each bone (local rotations would hide a parent's difference).
      const glm::quat qa = glm::quat_cast(glm::mat3(vrm->world(j))), qb = glm::quat_cast(glm::mat3(xpbd->world(j)));
      const double angle =
          2.0 * std::acos(std::min(1.0f, std::fabs(glm::dot(glm::normalize(qa), glm::normalize(qb))))) * 180.0 / M_PI;
      sum += angle;
      frame_sum += angle;
      ++count;
      double& max = f <= 120 ? a.max_first_2s_deg : a.max_after_2s_deg;
      max = std::max(max, angle);
    }
    a.final_mean_deg = frame_sum / rig->joints.size();
  }
  a.mean_deg = sum / count;
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out_path = argc > 1 ? argv[1] : "integrator_report.json";
#ifdef NDEBUG
  const char* build = "optimised";
#else
  const char* build = "debug (cost columns not meaningful)";
#endif
  const ParamSet param_sets[] = {{"aggressive", 4.0, 0.0, 2.0}, {"typical", 1.0, 0.4, 0.5}};
  const FramePattern patterns[] = {{"30fps+0.5s spikes", 1.0 / 30, 0.5, 2.0}, {"60fps", 1.0 / 60, 0, 0}};
  const char* rigs[] = {"hair100", "tail10"};
  json report = {
      {"build", build},
      {"vrm",
       {{"stepHz", integratorDefaults(Integrator::kVrm).step_hz},
        {"maxSubsteps", integratorDefaults(Integrator::kVrm).max_substeps}}},
      {"xpbd",
       {{"stepHz", integratorDefaults(Integrator::kXpbd).step_hz},
        {"maxSubsteps", integratorDefaults(Integrator::kXpbd).max_substeps},
        {"iterations", kDefaultXpbdIterations}}},
      {"stability",
       {{"secondsPerRow", kSeconds},
        {"motion", "rapid head shaking: +-1.2 rad yaw at 3 Hz, +-0.5 rad nod at 2 Hz, +-0.3 m sway at 1.1 Hz"},
        {"rows", json::array()}}},
      {"cost",
       {{"frames", "600 at 60 fps, rapid head shaking, typical parameters, best of 7"}, {"rows", json::array()}}},
      {"agreement", {{"frames", "20 s at 60 fps, walking and turning, typical parameters"}, {"rows", json::array()}}}};

  std::printf("springbones integrator report (%s build)\n", build);
  std::printf(
      "vrm = Instance (60 Hz, <= 4 steps/frame); xpbd = Instance, integrator xpbd (120 Hz, 4 iterations, <= 8 "
      "substeps/frame)\n");
  std::printf(
      "\nStability: %g s of rapid head shaking per row (explosion: non-finite or non-unit rotation, or length error > "
      "1%%)\n",
      kSeconds);
  std::printf("%-5s %-8s %-11s %-18s %7s %8s %12s %12s %6s %12s %16s\n", "integ", "rig", "params", "frames", "frames",
              "steps", "len err max", "len err end", "expl", "penetration", "swing m/s mean/max");
  for (const char* rig : rigs) {
    for (const ParamSet& p : param_sets) {
      for (const FramePattern& f : patterns) {
        for (const char* integrator : {"vrm", "xpbd"}) {
          const Stability r = runStability(integrator, rig, p, f);
          std::printf("%-5s %-8s %-11s %-18s %7lld %8lld %12.2e %12.2e %6lld %9.2f mm %9.2f/%.1f\n",
                      r.integrator.c_str(), r.rig.c_str(), r.params.c_str(), r.frames.c_str(), r.frame_count,
                      r.substeps, r.max_length_error, r.final_length_error, r.explosions, r.max_penetration * 1000,
                      r.mean_swing_speed, r.max_swing_speed);
          report["stability"]["rows"].push_back({{"integrator", r.integrator},
                                                 {"rig", r.rig},
                                                 {"params", r.params},
                                                 {"frames", r.frames},
                                                 {"joints", r.joints},
                                                 {"frameCount", r.frame_count},
                                                 {"steps", r.substeps},
                                                 {"maxLengthError", r.max_length_error},
                                                 {"finalLengthError", r.final_length_error},
                                                 {"explosions", r.explosions},
                                                 {"maxPenetrationM", r.max_penetration},
                                                 {"meanSwingSpeedMps", r.mean_swing_speed},
                                                 {"maxSwingSpeedMps", r.max_swing_speed}});
        }
      }
    }
  }

  std::printf("\nCost: time inside step(), 600 frames at 60 fps, best of 7\n");
  std::printf("%-9s %-8s %7s %10s %14s\n", "integ", "rig", "joints", "us/frame", "ns/joint-step");
  for (const char* rig : rigs) {
    for (const char* integrator : {"vrm", "xpbd", "xpbd-it2"}) {
      const Cost c = measureCost(integrator, rig);
      std::printf("%-9s %-8s %7zu %10.1f %14.1f\n", c.integrator.c_str(), c.rig.c_str(), c.joints, c.us_per_frame,
                  c.ns_per_joint_step);
      report["cost"]["rows"].push_back({{"integrator", c.integrator},
                                        {"rig", c.rig},
                                        {"joints", c.joints},
                                        {"usPerFrame", c.us_per_frame},
                                        {"nsPerJointStep", c.ns_per_joint_step}});
    }
  }

  std::printf("\nAgreement of xpbd with vrm: angle between the bones' world rotations, walking, typical parameters\n");
  std::printf("%-8s %10s %16s %16s %16s\n", "rig", "mean deg", "max deg, 0-2 s", "max deg, 2-20 s", "last frame mean");
  for (const char* rig : rigs) {
    const Agreement a = compareWithVrm(rig);
    std::printf("%-8s %10.2f %16.2f %16.2f %16.2f\n", a.rig.c_str(), a.mean_deg, a.max_first_2s_deg, a.max_after_2s_deg,
                a.final_mean_deg);
    report["agreement"]["rows"].push_back({{"rig", a.rig},
                                           {"meanDeg", a.mean_deg},
                                           {"maxDegFirst2s", a.max_first_2s_deg},
                                           {"maxDegAfter2s", a.max_after_2s_deg},
                                           {"lastFrameMeanDeg", a.final_mean_deg}});
  }

  std::ofstream out(out_path);
  out << report.dump(2) << "\n";
  if (!out) {
    std::fprintf(stderr, "could not write %s\n", out_path.c_str());
    return 1;
  }
  std::printf("\nwrote %s\n", out_path.c_str());
  return 0;
}
