// springbones: spring-bone physics for avatar wearables (Decentraland ADR-316, VRM family).
//
// The runtime's public C++ API (the VRM reader, the content hash, the JSON texts of the JavaScript
// boundary and the creator tools have their own headers beside this one). A wearable is loaded
// once into an immutable Rig (GLB hierarchy + data.springBones metadata -> flat list of simulated
// joints); every avatar wearing it gets its own Instance (simulation state). Per frame the caller
// writes driver world matrices, calls step(dt) and reads one local rotation per joint. Nothing
// here throws: failures come back as an Error, questionable input as Warnings.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace springbones {

// ---------------------------------------------------------------------------------------------
// Value types: plain floats in glTF's conventions, so that neither this header nor its callers
// need a maths library. The core computes in GLM and converts at its edges, bit for bit.

struct Vec3 {
  float x = 0.0f, y = 0.0f, z = 0.0f;
};
/// A unit quaternion in glTF's order: x, y, z, then w.
struct Quat {
  float x = 0.0f, y = 0.0f, z = 0.0f, w = 1.0f;
};
/// A 4x4 matrix, column-major as glTF stores it (m[12..14]: the translation); identity by default.
struct Mat4 {
  float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
};

// ---------------------------------------------------------------------------------------------
// Errors and warnings

enum class ErrorCode : int {
  kOk = 0,
  kInvalidArgument = 1,           ///< null buffer, bad option value
  kGlbTruncated = 2,              ///< header or chunk extends past the end of the buffer
  kGlbBadMagic = 3,               ///< neither a GLB ("glTF" magic) nor glTF JSON text
  kGlbBadChunk = 4,               ///< GLB version or chunk layout we cannot read
  kGltfBadJson = 5,               ///< the glTF JSON does not parse
  kGltfInvalid = 6,               ///< JSON parses but is not a usable glTF (bad node fields...)
  kHierarchyMultipleParents = 7,  ///< a node listed as child of two parents
  kHierarchyCycle = 8,            ///< a node is its own ancestor
  kMetadataBadJson = 9,           ///< springBones JSON text does not parse
  kMetadataInvalid = 10,          ///< springBones has a shape we cannot use (models not an object)
  kLimitExceeded = 11,            ///< more nodes / bytes than the documented limits
};

/// Stable lower-case identifier of a code ("glb-truncated", ...), used by the JS error codes.
const char* errorCodeName(ErrorCode code);

struct Error {
  ErrorCode code = ErrorCode::kOk;
  std::string message;
  std::string path;  ///< JSON path for metadata errors ("/models/<hash>/<bone>"), else empty
  explicit operator bool() const { return code != ErrorCode::kOk; }
};

struct Warning {
  std::string code;     ///< stable identifier, e.g. "center-not-found"
  std::string message;  ///< human readable, names the node or field
  std::string path;     ///< JSON path into springBones when the warning is about metadata
};

// ---------------------------------------------------------------------------------------------
// Limits we impose on untrusted input (docs/input.md; exceeding one is an Error).

inline constexpr std::size_t kMaxNodes = 262144;
inline constexpr std::size_t kMaxGltfJsonBytes = 64u << 20;
inline constexpr std::size_t kMaxMetadataBytes = 16u << 20;

// ---------------------------------------------------------------------------------------------
// The GLB node hierarchy

struct Transform {
  Vec3 translation;
  Quat rotation;
  Vec3 scale{1.0f, 1.0f, 1.0f};
};

struct SkeletonNode {
  std::string name;
  int parent = -1;  ///< index into Skeleton::nodes, -1 for a scene root
  std::vector<int> children;
  Transform rest_local;  ///< from TRS, or decomposed from `matrix`
  Mat4 rest_world;       ///< product of the rest locals from the root down
};

struct Skeleton {
  std::vector<SkeletonNode> nodes;  ///< glTF order
  std::vector<int> parents_first;   ///< every node index, each after its parent
};

// Reading it: loadSkeleton, from typed input (typed_input.h) or, with the readers, from bytes
// (readers.h).

// ---------------------------------------------------------------------------------------------
// data.springBones parameters (ADR-316 table). Ranges are inclusive.

struct BoneParams {
  float stiffness = 2.0f;               ///< [0, 4], pull back to the rest direction, m/s
  float gravity_power = 0.0f;           ///< [0, 2], gravity impulse, m/s
  Vec3 gravity_dir{0.0f, -1.0f, 0.0f};  ///< world direction, normalized at parse time
  float drag = 0.5f;                    ///< [0, 1], fraction of velocity lost per step
};

struct BoneEntry {
  std::string name;  ///< glTF node name, case-sensitive
  BoneParams params;
  bool is_root = false;
  bool has_center = false;  ///< the entry has a "center" key (a null center means world space)
  std::string center;       ///< node name; empty with has_center means explicitly world space
};

struct ModelEntry {
  bool enabled = false;          ///< false: no entry for the hash, bad version, or no springBones at all
  std::string path;              ///< JSON path of models[hash] ("/models/<hash>"), when enabled
  std::vector<BoneEntry> bones;  ///< in key order (the JSON reader sorts object keys)

  /// The JSON path of one of its entries, for warnings: path + the name as a pointer token. Built
  /// when a warning needs it: one string per entry was a tenth of reading 5,000 entries.
  std::string entryPath(const BoneEntry& bone) const;
};

/// True when a node name contains "springbone", ASCII case-insensitive (the ADR's discovery rule).
bool isSpringBoneName(const std::string& name);

// ---------------------------------------------------------------------------------------------
// The rig: immutable, shared by every avatar wearing the same item

/// An angle limit on a joint (VRMC_springBone_limit 1.0-draft): the directions its bone may point
/// in, in the joint's limit space, which is the joint's rest world rotation under its current
/// parent, then the turn taking +Y onto the rest bone axis, then `rotation`
/// (docs/semantics.md, "Angle limits").
struct JointLimit {
  enum class Kind { kNone, kCone, kHinge, kSpherical };
  Kind kind = Kind::kNone;
  float angle = 0.0f;  ///< cone, hinge: the widest angle from the limit's +Y, [0, pi]
  float pitch = 0.0f;  ///< spherical: the largest turn about the limit's X, [0, pi]
  float yaw = 0.0f;    ///< spherical: the largest turn toward the limit's X, [0, pi / 2]
  Quat rotation;       ///< the limit's turn from its default orientation, unit
};

struct Joint {
  int node = -1;           ///< the bone this joint rotates
  int tail_node = -1;      ///< its first child: where the bone ends; -1 when the tail is no node
                           ///< (a VRM 0.x leaf's virtual tail): tail_local is authoritative
  int parent_joint = -1;   ///< joint of the glTF parent, -1 for a chain root
  int parent_driver = -1;  ///< for a chain root: driver holding its parent's world matrix
                           ///< (-1: the root is a scene root, its parent is the identity)
  int center_driver = -1;  ///< driver whose space holds the inertia, -1 for world space
  int chain = -1;          ///< index of the chain root joint
  BoneParams params;
  Transform rest_local;   ///< the node's rest local transform
  Vec3 tail_local;        ///< tail position in the joint's local space (child translation)
  float rest_length = 0;  ///< world distance head->tail in the rest pose
  float hit_radius = 0;   ///< radius of the tail against colliders, world units
  /// indices into Rig::colliders this joint's tail collides with, in the order it tests them; a
  /// collider listed by two of a VRM spring's collider groups is here twice (it pushes twice)
  std::vector<int> colliders;
  JointLimit limit;  ///< kNone: the joint may point anywhere
};

struct Driver {
  int node = -1;  ///< -1: a node the GLB does not have (a collider on an avatar bone); the caller
                  ///< still writes its world matrix, found by name
  std::string name;
};

/// A collision shape (VRMC_springBone colliders, and the plane and inside shapes of
/// VRMC_springBone_extended_collider), in the space of the node that carries it.
struct ColliderShape {
  enum class Shape { kSphere, kCapsule, kPlane };
  Shape shape = Shape::kSphere;
  /// Sphere and capsule only: the tail is kept inside the shape rather than pushed out of it.
  bool inside = false;
  Vec3 offset;                    ///< sphere center / capsule start / a point of the plane
  Vec3 tail;                      ///< capsule end
  Vec3 normal{0.0f, 0.0f, 1.0f};  ///< plane only: the side tails are kept on
  float radius = 0.0f;            ///< in the node's space (world radius = radius x its scale); 0 for a plane
};

/// A collider of the rig, carried by a driver's world matrix.
struct Collider : ColliderShape {
  int driver = -1;
};

/// A collider to attach by node name, for avatars whose GLB says nothing about colliders.
struct ColliderSpec : ColliderShape {
  std::string node;
};

/// Ready-made collider sets a rig can ask for by name (RigOptions::preset).
enum class ColliderPreset {
  kNone,
  /// Decentraland's body: head sphere, neck capsule, two chest capsules, shoulder and upper-arm
  /// capsules, sized from the rest lengths of the 62-bone armature's bones in the GLB
  /// (body_colliders.h; docs/semantics.md, "Body colliders").
  kDclBody,
};

/// The largest entry of a driver matrix an instance takes (Instance::driverMatrices): a matrix with
/// a larger (or non-finite) entry is ignored for the frame, and the driver keeps its last good
/// pose. 10^12 world units, or a scale of 10^12: far beyond any scene, and small enough that the
/// squares, products and determinants the step takes of it stay finite in float, so that every
/// world matrix does.
inline constexpr float kMaxDriverEntry = 1e12f;

/// The largest hitRadius a rig takes (world units): beyond it (or infinite) it is clamped, NaN or
/// below 0 is 0, each with the warning `hit-radius-out-of-range`. Far beyond any avatar, and
/// small enough that the squared distances it makes stay finite in float.
inline constexpr float kMaxHitRadius = 1e6f;
/// The largest collider radius and offset or tail component (the node's units) a rig takes: a
/// collider beyond it is ignored with `collider-invalid`, as a non-finite one is.
inline constexpr float kMaxColliderSize = 1e6f;

/// One bone of the avatar a wearable is worn on: its armature name and its rest world matrix (the
/// avatar's world space in its rest pose). The 'dcl-body' preset measures its shapes on these.
struct AvatarBone {
  std::string name;
  Mat4 rest_world;
};

struct RigOptions {
  std::vector<ColliderSpec> colliders;            ///< every joint collides with all of them
  ColliderPreset preset = ColliderPreset::kNone;  ///< shapes added before `colliders`
  /// The avatar's bones, for the preset: when given, every shape is measured on them (the first of
  /// each name), not on the bones the wearable's GLB carries, and is carried by the avatar's bone
  /// of that name (a driver the caller supplies when the GLB lacks it). Empty: the GLB's bones.
  std::vector<AvatarBone> avatar_bones;
  float hit_radius = 0.0f;  ///< joint radius against them, world units, in [0, kMaxHitRadius]
  /// Angle limits by joint node name (the standard's metadata has no field for them). Values out of
  /// the draft's ranges are clamped, a name that is no simulated joint is dropped, with warnings.
  std::map<std::string, JointLimit> limits;
};

/// The 'dcl-body' preset as one instance wants it (Instance::setColliders): every shape's radius
/// times `scale` (the capsules still run between their bones: lengths are the avatar's), and the
/// shapes named in `omit` left out (dclBodyShapeNames: "head", "neck", "chest", "upper-belly",
/// "left-shoulder", "right-shoulder", "left-upper-arm", "right-upper-arm").
struct BodyColliderOptions {
  float scale = 1.0f;  ///< finite, >= 0; a radius it takes beyond kMaxColliderSize: collider-invalid
  std::vector<std::string> omit;
};

/// The names of the 'dcl-body' preset's shapes, in the order it builds them.
const std::vector<std::string>& dclBodyShapeNames();

/// What Instance::setColliders takes: the shapes of RigOptions' `colliders` and `preset`, by the
/// same rules, and the preset's per-instance size and omissions.
struct ColliderOptions {
  std::vector<ColliderSpec> colliders;            ///< every joint collides with all of them
  ColliderPreset preset = ColliderPreset::kNone;  ///< shapes added before `colliders`
  std::vector<AvatarBone> avatar_bones;           ///< as RigOptions::avatar_bones, for the preset
  BodyColliderOptions body;                       ///< the preset's scale and omissions
};

struct RigConstants;  // what the simulation derives from a rig (src/simulation/rig_constants.h)

struct Rig {
  Skeleton skeleton;
  std::vector<Joint> joints;     ///< parents before children
  std::vector<Driver> drivers;   ///< chain-root parents and center nodes, in first-use order
  std::vector<int> chain_roots;  ///< joint indices of the roots
  std::vector<Collider> colliders;
  /// How many times the VRM update moves a tail out of the joint's colliders per step, each pass
  /// every collider with the bone length restored after each push, stopping at a pass that moves
  /// nothing. 1 is the VRM update; the body preset asks for more, so that a bone lying across the
  /// thin neck does not leave its tail inside it (docs/semantics.md, "Body colliders"). XPBD
  /// iterates its constraints on its own (xpbdIterations).
  int collider_passes = 1;
  std::vector<Warning> warnings;
  /// What the simulation derives from the rig, computed once and shared by the rig's instances
  /// (with the lane pool of the fast path): made by the first instance, freed with the last.
  /// Written by the instances, so a rig and its instances belong to one thread at a time
  /// (docs/design.md, "Threads").
  mutable std::weak_ptr<const RigConstants> constants;
};

/// Builds the chains of a skeleton from the chosen metadata entry (the rules: docs/semantics.md).
/// Never fails: problems become warnings and the affected joints are left out or fall back.
/// Collider nodes (found by name in the GLB, or else external drivers the caller supplies) join
/// the driver list.
std::shared_ptr<const Rig> buildRig(Skeleton skeleton, const ModelEntry& model, std::vector<Warning> warnings = {},
                                    const RigOptions& options = {});

// ---------------------------------------------------------------------------------------------
// The simulation: one Instance per avatar

/// Which update moves the joints. kVrm is the VRM spring-bone update (docs/semantics.md, The step);
/// kXpbd the XPBD integrator of xpbd_solver.h (exact bone lengths, compliant constraints, meant
/// for 120 Hz substeps), driven by the same parameters.
enum class Integrator { kVrm, kXpbd };

// Limits and defaults of InstanceOptions, defined here only (the JS API reads them from the
// module, see boundary.h describeLimits).
inline constexpr double kMinStepHz = 1.0;
inline constexpr double kMaxStepHz = 1000.0;
inline constexpr int kMaxSubsteps = 64;
inline constexpr int kMaxXpbdIterations = 64;
inline constexpr int kDefaultXpbdIterations = 4;

/// Jump detection (InstanceOptions::jump_distance / jump_angle): a driver that moves farther than
/// this in one frame, per fixed step of the frame, is a discontinuity (a teleport, a cut) rather
/// than motion. 0.5 m per step is 30 m/s at 60 Hz, 0.5 rad per step about 1,700 degrees per
/// second: far beyond a run, an emote or a turn (docs/semantics.md, Jumps).
inline constexpr float kDefaultJumpDistance = 0.5f;
inline constexpr float kDefaultJumpAngle = 0.5f;

/// Instance::settle: the simulated time it runs by default and at most (seconds; its steps are
/// this times the step rate).
inline constexpr double kDefaultSettleSeconds = 2.0;
inline constexpr double kMaxSettleSeconds = 60.0;

/// InstanceOptions::inertia and Instance::setInertia: 1, every chain feels all of its driver's
/// motion (the VRM update as it is).
inline constexpr float kDefaultInertia = 1.0f;

/// The step rate and substep cap an integrator runs at unless told otherwise.
struct IntegratorDefaults {
  double step_hz;
  int max_substeps;
};
/// kVrm: 60 Hz, 4 substeps (the rate the VRM parameters are defined at). kXpbd: 120 Hz substeps
/// (what its compliant constraints are meant for), 8 of them to cover a 15 fps frame.
constexpr IntegratorDefaults integratorDefaults(Integrator integrator) {
  return integrator == Integrator::kXpbd ? IntegratorDefaults{120.0, 8} : IntegratorDefaults{60.0, 4};
}

struct InstanceOptions {
  /// fixed simulation rate, [kMinStepHz, kMaxStepHz]; 0 (or any value not above 0): the
  /// integrator's default
  double step_hz = 0.0;
  /// steps per frame at most, [1, kMaxSubsteps], surplus time is dropped; 0 (or less): the
  /// integrator's default
  int max_substeps = 0;
  Integrator integrator = Integrator::kVrm;
  int xpbd_iterations = kDefaultXpbdIterations;  ///< kXpbd only: constraint passes per substep, [1, 64]
  /// A driver translating farther than this (world units) per step of a frame is a jump, whose
  /// chains are carried across it (Instance::jump). Not a finite number above 0: detection off.
  float jump_distance = kDefaultJumpDistance;
  /// The same for a driver's rotation, radians per step. Not a finite number above 0: off.
  float jump_angle = kDefaultJumpAngle;
  /// How much of the motion of the driver a chain hangs from its tails feel, in [0, 1], for every
  /// chain (Instance::setInertia sets one chain): 1 the whole motion (the VRM update), 0 none, as
  /// if the chain's inertia were kept in that driver's space (docs/semantics.md, "Inertia of the
  /// avatar"). Clamped to [0, 1]; NaN: 1.
  float inertia = kDefaultInertia;
};

/// A wind blowing on every joint of an instance: a pull on each tail like gravityPower's, world
/// space, with gusts that are a seeded function of the instance's simulated time (windAt), so the
/// same seed gives the same motion, natively and in WebAssembly (docs/semantics.md, "Wind").
struct Wind {
  Vec3 direction{1.0f, 0.0f, 0.0f};  ///< world direction; zero or non-finite: no wind
  float strength = 0.0f;             ///< [0, kMaxWindStrength], world units per second
  float gust_frequency = 0.0f;       ///< [0, kMaxGustFrequency], gusts per second; 0: steady
  std::uint32_t seed = 0;            ///< picks the gust sequence
};
inline constexpr float kMaxWindStrength = 10.0f;
inline constexpr float kMaxGustFrequency = 10.0f;

class Instance {
 public:
  /// The rig must outlive nothing: the instance keeps it alive. Options out of range are clamped,
  /// options left at 0 take the integrator's defaults; options() has the values in use.
  explicit Instance(std::shared_ptr<const Rig> rig, InstanceOptions options = {});
  ~Instance();
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  /// Column-major 4x4 world matrices, 16 floats per driver, written by the caller before step().
  /// A matrix with an entry that is not a number within ±kMaxDriverEntry is ignored for the frame:
  /// the driver keeps its last good pose (its rest pose before any).
  float* driverMatrices();
  std::size_t driverCount() const;
  /// Local rotations (x, y, z, w), 4 floats per joint, valid after construction (rest pose).
  const float* rotations() const;
  /// Column-major world matrices of the joints after the last step, 16 floats per joint (for
  /// drawing the chains or writing bone.matrixWorld directly).
  const float* worldMatrices() const;
  std::size_t jointCount() const;

  /// Advances by a frame of dt seconds. dt <= 0 or non-finite: nothing happens.
  void step(double dt);
  /// step(dt) for each of `count` instances (distinct, not null), with the same results, but the
  /// instances of one rig on the fast path go through each step together (one kernel run for all
  /// of them).
  static void stepAll(Instance* const* instances, std::size_t count, double dt);
  /// Forgets the motion; the next step re-seeds the tails at rest under the current drivers.
  void reset();
  /// Treats the driver change before the next step as a discontinuity (an animation starting, a
  /// cut): every chain is carried across it with the jump of the driver it hangs from, keeping its
  /// shape and its motion relative to the avatar and adding no velocity. Drivers moving beyond
  /// jump_distance or jump_angle per step do the same on their own.
  void jump();
  /// Discontinuities carried so far (jump() calls that reached a step and detected jumps).
  int jumps() const;
  /// Takes over the motion of `previous`, an instance of another rig read from the same skeleton
  /// (the rig rebuilt with edited parameters or chains), so that the edit neither pops nor
  /// restarts the chains. Call it after writing this instance's driver matrices with the pose the
  /// previous instance last stepped under, before this instance's first step. This instance is
  /// seeded at rest under those drivers; then every joint that was a joint of `previous` (the same
  /// node, name and tail node) takes its tail state over (position and velocity, moved into this
  /// joint's center space when the center changed) and its last rotation; the step clock (the
  /// time left over, the wind's time and wind) carries over. Joints new to this rig start at rest.
  /// Nothing happens when `previous` has never stepped (this instance then seeds on its first step)
  /// or is this instance.
  void carryFrom(const Instance& previous);
  /// Changes the thresholds of jump detection (the options' rules); a NaN keeps that one as it is.
  void setJumpThresholds(float distance, float angle);
  /// Sets the wind on this instance, from its next step on (a Scene's setWind sets it on every
  /// member). Out-of-range values are clamped: strength and gust_frequency to their ranges (NaN:
  /// 0), the direction normalized (zero or non-finite: no wind).
  void setWind(const Wind& wind);
  /// The wind in use, as clamped by setWind.
  const Wind& wind() const;
  /// Runs the springs to rest under the current driver matrices, without a frame: every tail is
  /// put where its stiffness, gravity and wind balance (parents first), then stepped with no
  /// velocity, which resolves colliders (and a grab), until no joint turns by more than 1e-5 rad
  /// in a step, or for at most `seconds` x the step rate steps (seconds clamped to
  /// [0, kMaxSettleSeconds]; NaN: 0; 0 leaves the tails at rest, as reset() would). The wind pulls as at the current
  /// simulated time, which does not advance. The motion is then forgotten: the next step starts from the settled pose
  /// with no velocity, and the drivers as they are count as the last frame's. Deterministic (the same pose, the same
  /// result); returns the steps it ran (0: none, the pose is the rest pose put in place). docs/semantics.md, "Settle".
  int settle(double seconds = kDefaultSettleSeconds);
  /// Holds joint `joint`'s tail toward `point` (world) from the next step on: every step, the
  /// joints from its chain root down to it turn so that it reaches toward the point as far as the
  /// chain reaches (one pass of backward and forward reaching per step), colliders (and limits)
  /// still holding; the joints below it swing as usual. Call it every frame with a moving point;
  /// a joint index out of range or a non-finite point does nothing. docs/semantics.md, "Grab".
  void grab(std::size_t joint, const Vec3& point);
  /// Lets go of the grabbed joint: the chain swings back from where and how fast it was moving.
  void release();
  /// The joint held by grab(), or -1.
  int grabbedJoint() const;
  /// Sets the inertia (InstanceOptions::inertia) of chain `chain` (an index into
  /// Rig::chain_roots), or of every chain for a negative one, from the next step on; clamped to
  /// [0, 1], NaN: 1; a chain out of range does nothing.
  void setInertia(float value, int chain = -1);
  /// The inertia of chain `chain` (kDefaultInertia for one out of range).
  float inertia(std::size_t chain) const;
  /// Replaces the instance's colliders (every one it has, its rig's included) from its next step
  /// on, for whichever integrator runs it: every joint then collides with all of the new ones, in
  /// order, with its rig's hitRadius. The shapes follow RigOptions' rules and warnings
  /// (collider-invalid, collider-on-spring-bone, body-collider-skipped), returned rather than kept.
  /// A collider's node is one of the rig's drivers when one is named so (the first node of that
  /// name, else an avatar bone the rig supplies by name), else a frame: a world matrix the caller
  /// writes every frame (frameMatrices), as it writes the drivers. The rig's own colliders given
  /// again move the tails bit for bit as before. An instance whose colliders differ from its
  /// rig's in number, kind or which joints meet them steps on the general path, never the lanes
  /// (the same update). Allocates here, never in the steps.
  std::vector<Warning> setColliders(const ColliderOptions& options);
  /// The frames setColliders made, by name, in the order of frameMatrices.
  const std::vector<std::string>& frameNames() const;
  /// Column-major 4x4 world matrices, 16 floats per frame, written by the caller before step():
  /// what the colliders on that frame follow, held for every step of the frame (not interpolated
  /// across its substeps, as drivers are). An entry that is not a number within +-kMaxDriverEntry
  /// leaves the frame at its last good matrix; until written, a frame is the avatar bone's rest
  /// matrix (ColliderOptions::avatar_bones), else the GLB node's of that name, else the identity. Moves when
  /// setColliders runs again.
  float* frameMatrices();

  /// Fixed steps the last frame ran (step, stepAll or Scene::step): 0 when dt was too short to
  /// reach the next step, was <= 0 or non-finite, or a scene's budget held the instance;
  /// max_substeps when the frame was longer than that many steps and its excess was dropped.
  int lastSteps() const;

  const Rig& rig() const;
  const InstanceOptions& options() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// ---------------------------------------------------------------------------------------------
// Many avatars: one call per frame for a whole page

/// Steps every added instance in one call. With a budget, only the `max_active` instances nearest
/// to the viewer are simulated; the others hold their last pose and are re-seeded (reset) when
/// they come back into the budget, as the in-world renderer does with its nearest avatars.
/// Instances are not owned: remove one before destroying it.
class Scene {
 public:
  /// Adds an instance (ignored if already present) and returns its slot in positions().
  std::size_t add(Instance* instance);
  void remove(Instance* instance);
  std::size_t size() const { return members_.size(); }

  /// x, y, z per instance in slot order, written by the caller (e.g. each avatar's root position).
  /// Slots shift down when an instance is removed.
  float* positions() { return positions_.data(); }

  /// max_active < 0: no budget, every instance steps. Non-finite viewer coordinates are ignored.
  void setBudget(int max_active, const Vec3& viewer);

  /// Sets the wind of every instance in the scene, and of every one added later (an instance's own
  /// setWind afterwards overrides it for that instance until the scene's wind is set again).
  void setWind(const Wind& wind);

  /// Steps the active instances by dt (same rules as Instance::step).
  void step(double dt);
  /// Whether the instance in `slot` was simulated by the last step.
  bool isActive(std::size_t slot) const { return slot < active_.size() && active_[slot] != 0; }
  /// isActive for every slot at once, 1 or 0 per slot in slot order (moves with add and remove).
  const unsigned char* activeFlags() const { return active_.data(); }

 private:
  std::vector<Instance*> members_;
  std::vector<float> positions_;
  std::vector<unsigned char> active_;
  std::vector<std::pair<double, std::size_t>> by_distance_;  // scratch, kept to avoid allocation
  std::vector<Instance*> stepping_;                          // scratch: this step's instances
  int max_active_ = -1;
  Vec3 viewer_;
  bool has_wind_ = false;
  Wind wind_;
};

}  // namespace springbones
