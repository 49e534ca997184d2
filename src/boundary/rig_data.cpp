// A rig as bytes (springbones/boundary.h, writeRigData / readRigData): how a rig built in the
// readers module (loadVrm) crosses into the runtime module, which runs it. The layout is described
// once, by rigFields below, which both the writer and the reader walk, so the two cannot disagree
// on a field. Little-endian 32-bit values (WebAssembly's byte order, and the native targets'):
//   u32 magic, u32 version, then the rig's fields in rigFields's order: a list is a u32 count and
//   its items, a string a u32 length and its bytes, an int an i32, a float its f32 bits (exact:
//   the runtime steps the very floats the readers computed).
// Both modules come from one build, so the reader checks the framing rather than trusting it:
// every read stays inside the bytes, every count fits in what is left, every index points into a
// list read before it (or is -1), and a layout of another version is refused.
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "springbones/boundary.h"

namespace springbones {
namespace {

constexpr std::uint32_t kRigDataMagic = 0x67697242;  // "Brig" in the bytes' order
constexpr std::uint32_t kRigDataVersion = 1;

class RigDataWriter {
 public:
  explicit RigDataWriter(std::vector<std::uint8_t>& out) : out_(out) {}
  void raw(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const std::uint8_t*>(data);
    out_.insert(out_.end(), bytes, bytes + size);
  }
  void u32(std::uint32_t& v) { raw(&v, 4); }
  void i32(int& v) { raw(&v, 4); }
  void f32(float& v) { raw(&v, 4); }
  void index(int& v, std::size_t /*bound*/) { i32(v); }
  template <typename Enum>
  void enumeration(Enum& v, std::uint32_t /*count*/) {
    auto n = static_cast<std::uint32_t>(v);
    u32(n);
  }
  void flag(bool& v) {
    std::uint32_t n = v ? 1 : 0;
    u32(n);
  }
  void string(std::string& s) {
    auto n = static_cast<std::uint32_t>(s.size());
    u32(n);
    raw(s.data(), s.size());
  }
  template <typename T, typename Each>
  void list(std::vector<T>& items, Each&& each) {
    auto n = static_cast<std::uint32_t>(items.size());
    u32(n);
    for (T& item : items) each(item);
  }

 private:
  std::vector<std::uint8_t>& out_;
};

class RigDataReader {
 public:
  RigDataReader(const std::uint8_t* data, std::size_t size) : at_(data), end_(data + size) {}
  bool ok() const { return ok_; }
  bool atEnd() const { return at_ == end_; }
  void raw(void* data, std::size_t size) {
    if (!ok_ || static_cast<std::size_t>(end_ - at_) < size) {
      ok_ = false;
      std::memset(data, 0, size);
      return;
    }
    std::memcpy(data, at_, size);
    at_ += size;
  }
  void u32(std::uint32_t& v) { raw(&v, 4); }
  void i32(int& v) { raw(&v, 4); }
  void f32(float& v) { raw(&v, 4); }
  /// An index into a list of `bound` items, or -1.
  void index(int& v, std::size_t bound) {
    i32(v);
    if (v < -1 || (v >= 0 && static_cast<std::size_t>(v) >= bound)) ok_ = false;
  }
  template <typename Enum>
  void enumeration(Enum& v, std::uint32_t count) {
    std::uint32_t n = 0;
    u32(n);
    if (n >= count) ok_ = false;
    v = static_cast<Enum>(ok_ ? n : 0);
  }
  void flag(bool& v) {
    std::uint32_t n = 0;
    u32(n);
    if (n > 1) ok_ = false;
    v = n == 1;
  }
  void string(std::string& s) {
    std::uint32_t n = 0;
    u32(n);
    if (!fits(n, 1)) return;
    s.assign(reinterpret_cast<const char*>(at_), n);
    at_ += n;
  }
  /// Every item takes at least 4 bytes, so a count the rest of the bytes cannot hold is refused
  /// before anything is allocated for it.
  template <typename T, typename Each>
  void list(std::vector<T>& items, Each&& each) {
    std::uint32_t n = 0;
    u32(n);
    if (!fits(n, 4)) return;
    items.resize(n);
    for (T& item : items) {
      each(item);
      if (!ok_) return;
    }
  }

 private:
  bool fits(std::uint32_t count, std::size_t item_bytes) {
    if (ok_ && count > static_cast<std::size_t>(end_ - at_) / item_bytes) ok_ = false;
    return ok_;
  }
  const std::uint8_t* at_;
  const std::uint8_t* end_;
  bool ok_ = true;
};

template <typename Io>
void vec3(Io& io, Vec3& v) {
  io.f32(v.x);
  io.f32(v.y);
  io.f32(v.z);
}

template <typename Io>
void quat(Io& io, Quat& q) {
  io.f32(q.x);
  io.f32(q.y);
  io.f32(q.z);
  io.f32(q.w);
}

template <typename Io>
void transform(Io& io, Transform& t) {
  vec3(io, t.translation);
  quat(io, t.rotation);
  vec3(io, t.scale);
}

template <typename Io>
void params(Io& io, BoneParams& p) {
  io.f32(p.stiffness);
  io.f32(p.gravity_power);
  vec3(io, p.gravity_dir);
  io.f32(p.drag);
}

template <typename Io>
void shape(Io& io, ColliderShape& c) {
  io.enumeration(c.shape, 3);
  io.flag(c.inside);
  vec3(io, c.offset);
  vec3(io, c.tail);
  vec3(io, c.normal);
  io.f32(c.radius);
}

template <typename Io>
void limit(Io& io, JointLimit& l) {
  io.enumeration(l.kind, 4);
  io.f32(l.angle);
  io.f32(l.pitch);
  io.f32(l.yaw);
  quat(io, l.rotation);
}

// The layout: every field of a Rig (the constants the instances derive are not part of it) and the
// format its springs were read from. The lists an index points into come before it.
template <typename Io>
void rigFields(Io& io, Rig& rig, VrmSpringFormat& format) {
  auto& nodes = rig.skeleton.nodes;
  io.list(nodes, [&](SkeletonNode& n) {
    io.string(n.name);
    io.index(n.parent, nodes.size());
    io.list(n.children, [&](int& child) { io.index(child, nodes.size()); });
    transform(io, n.rest_local);
    for (float& f : n.rest_world.m) io.f32(f);
  });
  io.list(rig.skeleton.parents_first, [&](int& n) { io.index(n, nodes.size()); });
  io.list(rig.drivers, [&](Driver& d) {
    io.index(d.node, nodes.size());
    io.string(d.name);
  });
  io.list(rig.colliders, [&](Collider& c) {
    shape(io, c);
    io.index(c.driver, rig.drivers.size());
  });
  io.list(rig.joints, [&](Joint& j) {
    io.index(j.node, nodes.size());
    io.index(j.tail_node, nodes.size());
    io.index(j.parent_joint, rig.joints.size());
    io.index(j.parent_driver, rig.drivers.size());
    io.index(j.center_driver, rig.drivers.size());
    io.index(j.chain, rig.joints.size());
    params(io, j.params);
    transform(io, j.rest_local);
    vec3(io, j.tail_local);
    io.f32(j.rest_length);
    io.f32(j.hit_radius);
    io.list(j.colliders, [&](int& c) { io.index(c, rig.colliders.size()); });
    limit(io, j.limit);
  });
  io.list(rig.chain_roots, [&](int& j) { io.index(j, rig.joints.size()); });
  io.i32(rig.collider_passes);
  io.list(rig.warnings, [&](Warning& w) {
    io.string(w.code);
    io.string(w.message);
    io.string(w.path);
  });
  io.enumeration(format, 3);
}

}  // namespace

void writeRigData(const Rig& rig, VrmSpringFormat format, std::vector<std::uint8_t>& out) {
  out.clear();
  RigDataWriter writer(out);
  std::uint32_t magic = kRigDataMagic;
  std::uint32_t version = kRigDataVersion;
  writer.u32(magic);
  writer.u32(version);
  // The walk takes its fields by reference for the reader's sake; the writer only reads them.
  rigFields(writer, const_cast<Rig&>(rig), format);
}

Error readRigData(TypedBytes data, std::shared_ptr<const Rig>& out, VrmSpringFormat& format) {
  out.reset();
  format = VrmSpringFormat::kNone;
  RigDataReader reader(data.data, data.data == nullptr ? 0 : data.size);
  std::uint32_t magic = 0;
  std::uint32_t version = 0;
  reader.u32(magic);
  reader.u32(version);
  auto rig = std::make_shared<Rig>();
  VrmSpringFormat read = VrmSpringFormat::kNone;
  if (reader.ok() && magic == kRigDataMagic && version == kRigDataVersion) rigFields(reader, *rig, read);
  if (!reader.ok() || !reader.atEnd() || magic != kRigDataMagic || version != kRigDataVersion) {
    return Error{ErrorCode::kInvalidArgument,
                 "the rig data is not in this runtime's layout (a readers module from another build?)", ""};
  }
  format = read;
  out = std::move(rig);
  return {};
}

}  // namespace springbones
