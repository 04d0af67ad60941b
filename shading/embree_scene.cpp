// EmbreeScene: device, scene and one triangle geometry; refit/rebuild; filtered ray queries.
#include "shading/embree_scene.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <stdexcept>
#include <string>

namespace pleat {

namespace {

/// An RTCIntersectContext with the triangles to ignore appended; Embree hands the filter function the
/// pointer we passed, so the filter can cast back (the base must be the first member).
struct FilterContext {
  RTCIntersectContext base;
  const Index* ignore = nullptr;
  std::size_t ignore_count = 0;
};

/// Context filter: rejects hits on the ignored triangles (the one-ring of the ray's origin).
void ignore_listed_triangles(const RTCFilterFunctionNArguments* args) {
  const auto* context = reinterpret_cast<const FilterContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    const Index* end = context->ignore + context->ignore_count;
    if (std::find(context->ignore, end, prim) != end) args->valid[i] = 0;
  }
}

void init_context(FilterContext& context, IgnoredTriangles ignore) {
  rtcInitIntersectContext(&context.base);
  context.ignore = ignore.data();
  context.ignore_count = ignore.size();
  context.base.filter = ignore.empty() ? nullptr : &ignore_listed_triangles;
}

const char* error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_UNKNOWN:
      return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
  }
  return "unrecognised error";
}

float clamp_to_float(double t) {
  if (t >= static_cast<double>(std::numeric_limits<float>::max()))
    return std::numeric_limits<float>::infinity();
  return static_cast<float>(t);
}

}  // namespace

struct EmbreeScene::Impl {
  EmbreeSceneParams params;
  MeshTopology topology;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  RTCGeometry geometry = nullptr;
  float* vertices = nullptr;  // Embree-owned, 3 floats per vertex (+ Embree's padding)
  glm::dvec3 offset{0.0};     // world = stored + offset
  double diameter = 0.0;
  std::vector<Index> ring_begin;  // CSR: incident triangles of v are ring[ring_begin[v] .. ring_begin[v+1])
  std::vector<Index> ring;
  std::size_t refits = 0;
  std::size_t rebuilds = 0;

  ~Impl() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }

  void check(const char* what) const {
    const RTCError code = rtcGetDeviceError(device);
    if (code != RTC_ERROR_NONE)
      throw std::runtime_error(std::string("Embree: ") + what + ": " + error_name(code));
  }

  void validate(const Frame& frame) const {
    if (frame.positions.size() != topology.num_vertices)
      throw std::invalid_argument("EmbreeScene: frame has " + std::to_string(frame.positions.size()) +
                                  " positions, topology has " + std::to_string(topology.num_vertices) +
                                  " vertices");
    for (std::size_t i = 0; i < frame.positions.size(); ++i) {
      const glm::dvec3& p = frame.positions[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw std::invalid_argument("EmbreeScene: vertex " + std::to_string(i) +
                                    " has a non-finite position");
    }
  }

  /// Writes the frame's positions (relative to `offset`) into the vertex buffer; returns whether any float
  /// changed. Also refreshes the scene diameter.
  bool write_positions(const Frame& frame) {
    bool changed = false;
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < frame.positions.size(); ++i) {
      const glm::dvec3& p = frame.positions[i];
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
      const glm::dvec3 q = p - offset;
      for (int k = 0; k < 3; ++k) {
        const float f = static_cast<float>(q[k]);
        if (vertices[3 * i + k] != f) {
          vertices[3 * i + k] = f;
          changed = true;
        }
      }
    }
    diameter = frame.positions.empty() ? 0.0 : glm::length(hi - lo);
    return changed;
  }

  void build_scene(const Frame& frame, bool for_refit) {
    if (scene != nullptr) {
      rtcReleaseScene(scene);
      scene = nullptr;
      geometry = nullptr;
      vertices = nullptr;
    }
    scene = rtcNewScene(device);
    int flags = RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION;
    if (params.robust) flags |= RTC_SCENE_FLAG_ROBUST;
    if (for_refit) flags |= RTC_SCENE_FLAG_DYNAMIC;
    rtcSetSceneFlags(scene, static_cast<RTCSceneFlags>(flags));
    // Per-geometry quality (and so REFIT) is only honoured under a LOW-quality (two-level) scene.
    rtcSetSceneBuildQuality(scene, for_refit ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_MEDIUM);

    geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(geometry, for_refit ? RTC_BUILD_QUALITY_REFIT : RTC_BUILD_QUALITY_MEDIUM);
    vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), topology.num_vertices));
    auto* indices =
        static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                       3 * sizeof(unsigned), topology.triangles.size()));
    check("allocating buffers");
    for (std::size_t f = 0; f < topology.triangles.size(); ++f)
      for (int k = 0; k < 3; ++k) indices[3 * f + k] = topology.triangles[f][k];
    std::fill(vertices, vertices + 3 * static_cast<std::size_t>(topology.num_vertices), std::nanf(""));
    write_positions(frame);
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(scene, geometry, 0);
    rtcReleaseGeometry(geometry);  // the scene keeps it alive
    rtcCommitScene(scene);
    check("building the BVH");
    ++rebuilds;
  }
};

EmbreeScene::EmbreeScene(const MeshTopology& topology, const Frame& frame, const EmbreeSceneParams& params)
    : m_impl(std::make_unique<Impl>()) {
  Impl& s = *m_impl;
  s.params = params;
  s.topology = topology;
  for (std::size_t f = 0; f < topology.triangles.size(); ++f)
    for (Index v : topology.triangles[f])
      if (v >= topology.num_vertices)
        throw std::invalid_argument("EmbreeScene: triangle " + std::to_string(f) + " has vertex " +
                                    std::to_string(v) + " out of range");
  s.validate(frame);

  s.ring_begin.assign(topology.num_vertices + 1, 0);
  for (const Triangle& t : topology.triangles)
    for (Index v : t) ++s.ring_begin[v + 1];
  for (Index v = 0; v < topology.num_vertices; ++v) s.ring_begin[v + 1] += s.ring_begin[v];
  s.ring.resize(s.ring_begin.back());
  std::vector<Index> fill(s.ring_begin.begin(), s.ring_begin.end() - 1);
  for (std::size_t f = 0; f < topology.triangles.size(); ++f)
    for (Index v : topology.triangles[f]) {
      // A degenerate triangle may name a vertex twice: list it once.
      const auto begin = s.ring.begin() + s.ring_begin[v];
      const auto end = s.ring.begin() + fill[v];
      if (std::find(begin, end, static_cast<Index>(f)) == end) s.ring[fill[v]++] = static_cast<Index>(f);
    }
  // Close the gaps left by degenerate triangles (rare): compact the CSR.
  {
    std::vector<Index> compact_begin(topology.num_vertices + 1, 0);
    std::vector<Index> compact;
    compact.reserve(s.ring.size());
    for (Index v = 0; v < topology.num_vertices; ++v) {
      compact.insert(compact.end(), s.ring.begin() + s.ring_begin[v], s.ring.begin() + fill[v]);
      compact_begin[v + 1] = static_cast<Index>(compact.size());
    }
    s.ring_begin = std::move(compact_begin);
    s.ring = std::move(compact);
  }

  if (!frame.positions.empty()) {
    glm::dvec3 lo = frame.positions[0], hi = frame.positions[0];
    for (const glm::dvec3& p : frame.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    s.offset = 0.5 * (lo + hi);
  }

  s.device = rtcNewDevice(nullptr);
  if (s.device == nullptr)
    throw std::runtime_error(std::string("Embree: cannot create a device: ") +
                             error_name(rtcGetDeviceError(nullptr)));
  if (rtcGetDeviceProperty(s.device, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED) == 0)
    throw std::runtime_error(
        "Embree: this build lacks filter functions, which pleat needs to skip self-hits");
  s.build_scene(frame, s.params.mode == EmbreeSceneParams::BuildMode::Refit);
}

EmbreeScene::~EmbreeScene() = default;
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;

void EmbreeScene::update(const Frame& frame) {
  Impl& s = *m_impl;
  if (s.params.mode == EmbreeSceneParams::BuildMode::Rebuild) {
    rebuild(frame);
    return;
  }
  s.validate(frame);
  if (!s.write_positions(frame)) return;
  rtcUpdateGeometryBuffer(s.geometry, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcCommitGeometry(s.geometry);
  rtcCommitScene(s.scene);
  s.check("refitting the BVH");
  ++s.refits;
}

void EmbreeScene::rebuild(const Frame& frame) {
  Impl& s = *m_impl;
  s.validate(frame);
  s.build_scene(frame, s.params.mode == EmbreeSceneParams::BuildMode::Refit);
}

namespace {

/// An Embree ray from a query, in the scene's offset frame (positions are stored relative to `offset`).
void fill_ray(RTCRay& r, const RayQuery& ray, const glm::dvec3& offset) {
  const glm::dvec3 o = ray.origin - offset;
  r.org_x = static_cast<float>(o.x);
  r.org_y = static_cast<float>(o.y);
  r.org_z = static_cast<float>(o.z);
  r.dir_x = static_cast<float>(ray.direction.x);
  r.dir_y = static_cast<float>(ray.direction.y);
  r.dir_z = static_cast<float>(ray.direction.z);
  r.tnear = static_cast<float>(ray.tnear);
  r.tfar = clamp_to_float(ray.tfar);
  r.mask = ~0u;
}

}  // namespace

RayHit EmbreeScene::intersect(const RayQuery& ray, IgnoredTriangles ignore) const {
  const Impl& s = *m_impl;
  FilterContext context;
  init_context(context, ignore);
  RTCRayHit rh{};
  fill_ray(rh.ray, ray, s.offset);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(s.scene, &context.base, &rh);
  RayHit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.hit = true;
  hit.t = rh.ray.tfar;
  hit.triangle = rh.hit.primID;
  hit.u = rh.hit.u;
  hit.v = rh.hit.v;
  return hit;
}

bool EmbreeScene::occluded(const RayQuery& ray, IgnoredTriangles ignore) const {
  const Impl& s = *m_impl;
  FilterContext context;
  init_context(context, ignore);
  RTCRay r{};
  fill_ray(r, ray, s.offset);
  rtcOccluded1(s.scene, &context.base, &r);
  return r.tfar == -std::numeric_limits<float>::infinity();
}

namespace {

/// Rays of escaping_rays from one origin (in the scene's offset frame), all with tnear = t0 and tfar = inf.
struct RayFan {
  float ox, oy, oz, t0;
  std::span<const glm::vec3> directions;
};

constexpr float kOccluded = -std::numeric_limits<float>::infinity();  // Embree's tfar after a hit

/// Fills lane `lane` of an RTCRay (W = 1) or RTCRayW packet with ray `i` of the fan.
template <class Ray>
void fill_lane(Ray& r, int lane, const RayFan& fan, std::size_t i) {
  const glm::vec3& d = fan.directions[i];
  if constexpr (requires { r.org_x[0]; }) {
    r.org_x[lane] = fan.ox, r.org_y[lane] = fan.oy, r.org_z[lane] = fan.oz, r.tnear[lane] = fan.t0;
    r.dir_x[lane] = d.x, r.dir_y[lane] = d.y, r.dir_z[lane] = d.z, r.time[lane] = 0.0f;
    r.tfar[lane] = std::numeric_limits<float>::infinity(), r.mask[lane] = ~0u, r.id[lane] = unsigned(i),
    r.flags[lane] = 0;
  } else {
    r.org_x = fan.ox, r.org_y = fan.oy, r.org_z = fan.oz, r.tnear = fan.t0;
    r.dir_x = d.x, r.dir_y = d.y, r.dir_z = d.z, r.time = 0.0f;
    r.tfar = std::numeric_limits<float>::infinity(), r.mask = ~0u, r.id = unsigned(i), r.flags = 0;
  }
}

/// rtcOccluded4/8/16 over the fan, W lanes at a time (the last packet masked).
template <int W, class Packet, auto occluded>
void occluded_packets(RTCScene scene, RTCIntersectContext* context, const RayFan& fan,
                      std::span<std::uint8_t> escaped) {
  alignas(64) int valid[W];
  alignas(64) Packet packet;
  for (std::size_t begin = 0; begin < fan.directions.size(); begin += W) {
    const std::size_t count = std::min<std::size_t>(W, fan.directions.size() - begin);
    for (int lane = 0; lane < W; ++lane) {
      valid[lane] = std::size_t(lane) < count ? -1 : 0;
      fill_lane(packet, lane, fan, begin + std::min<std::size_t>(std::size_t(lane), count - 1));
    }
    occluded(valid, scene, context, &packet);
    for (std::size_t i = 0; i < count; ++i) escaped[begin + i] = packet.tfar[i] == kOccluded ? 0 : 1;
  }
}

/// rtcOccluded1M over chunks of 64 rays: enough for Embree to form packets, small enough for L1.
void occluded_stream(RTCScene scene, RTCIntersectContext* context, const RayFan& fan,
                     std::span<std::uint8_t> escaped) {
  constexpr std::size_t kChunk = 64;
  RTCRay rays[kChunk];
  for (std::size_t begin = 0; begin < fan.directions.size(); begin += kChunk) {
    const std::size_t count = std::min(kChunk, fan.directions.size() - begin);
    for (std::size_t i = 0; i < count; ++i) fill_lane(rays[i], 0, fan, begin + i);
    rtcOccluded1M(scene, context, rays, static_cast<unsigned>(count), sizeof(RTCRay));
    for (std::size_t i = 0; i < count; ++i) escaped[begin + i] = rays[i].tfar == kOccluded ? 0 : 1;
  }
}

void occluded_single(RTCScene scene, RTCIntersectContext* context, const RayFan& fan,
                     std::span<std::uint8_t> escaped) {
  RTCRay ray;
  for (std::size_t i = 0; i < fan.directions.size(); ++i) {
    fill_lane(ray, 0, fan, i);
    rtcOccluded1(scene, context, &ray);
    escaped[i] = ray.tfar == kOccluded ? 0 : 1;
  }
}

}  // namespace

const char* ray_call_name(EmbreeSceneParams::RayCall call) {
  using C = EmbreeSceneParams::RayCall;
  switch (call) {
    case C::Stream:
      return "stream";
    case C::Packet4:
      return "packet4";
    case C::Packet8:
      return "packet8";
    case C::Packet16:
      return "packet16";
    case C::Single:
      return "single";
  }
  return "?";
}

void EmbreeScene::escaping_rays(const glm::dvec3& origin, std::span<const glm::vec3> directions, double tnear,
                                IgnoredTriangles ignore, std::span<std::uint8_t> escaped) const {
  if (escaped.size() != directions.size())
    throw std::invalid_argument("EmbreeScene::escaping_rays: escaped.size() != directions.size()");
  const Impl& s = *m_impl;
  FilterContext context;
  init_context(context, ignore);
  if (s.params.coherent) context.base.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  const glm::dvec3 o = origin - s.offset;
  const RayFan fan{static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z),
                   static_cast<float>(tnear), directions};
  using C = EmbreeSceneParams::RayCall;
  switch (s.params.ray_call) {
    case C::Stream:
      return occluded_stream(s.scene, &context.base, fan, escaped);
    case C::Packet4:
      return occluded_packets<4, RTCRay4, rtcOccluded4>(s.scene, &context.base, fan, escaped);
    case C::Packet8:
      return occluded_packets<8, RTCRay8, rtcOccluded8>(s.scene, &context.base, fan, escaped);
    case C::Packet16:
      return occluded_packets<16, RTCRay16, rtcOccluded16>(s.scene, &context.base, fan, escaped);
    case C::Single:
      return occluded_single(s.scene, &context.base, fan, escaped);
  }
}

std::span<const Index> EmbreeScene::incident_triangles(Index v) const {
  const Impl& s = *m_impl;
  return {s.ring.data() + s.ring_begin[v], s.ring.data() + s.ring_begin[v + 1]};
}

const MeshTopology& EmbreeScene::topology() const { return m_impl->topology; }
double EmbreeScene::scene_diameter() const { return m_impl->diameter; }
std::size_t EmbreeScene::refits() const { return m_impl->refits; }
std::size_t EmbreeScene::rebuilds() const { return m_impl->rebuilds; }

}  // namespace pleat
