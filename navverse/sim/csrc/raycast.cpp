// navverse.sim._raycast: ray casting against a triangle mesh with Embree's 8-wide ray packets.
//
// The camera's primary rays and its shadow rays are coherent: eight neighbouring pixels' rays start
// at one eye (or on one surface) and point nearly one way, so Embree traverses its BVH once for the
// eight of them (rtcIntersect8 / rtcOccluded8) instead of once per ray. Rays are taken eight at a
// time in the order given; a ray's packet depends only on its index, so results do not depend on the
// number of threads. The system Embree 3 is used (Debian/Ubuntu package libembree-dev); it chooses its
// own SIMD code for the machine at run time.
#include <embree3/rtcore.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace py = pybind11;

namespace {

constexpr int kPacket = 8;
constexpr int64_t kPacketsPerTask = 64;  // 512 rays per unit of work handed to a thread
constexpr float kInfinity = std::numeric_limits<float>::infinity();

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<uint32_t, py::array::c_style | py::array::forcecast>;

// Runs task(first, last) over [0, count) in pieces of `chunk`, on `threads` threads (0: every core).
template <typename Task>
void parallel_chunks(int64_t count, int64_t chunk, int threads, Task task) {
  if (threads <= 0) threads = std::max(1u, std::thread::hardware_concurrency());
  const int64_t pieces = (count + chunk - 1) / chunk;
  threads = static_cast<int>(std::min<int64_t>(threads, std::max<int64_t>(pieces, 1)));
  std::atomic<int64_t> next(0);
  auto worker = [&]() {
    for (;;) {
      const int64_t piece = next.fetch_add(1);
      if (piece >= pieces) break;
      task(piece * chunk, std::min(count, (piece + 1) * chunk));
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& thread : pool) thread.join();
}

// Loads rays [first, first + 8) (fewer at the end: the rest invalid) into a packet.
template <typename Packet>
void load_packet(const float* rays, int64_t first, int64_t count, float tfar, Packet& ray, int* valid) {
  for (int k = 0; k < kPacket; ++k) {
    const int64_t i = first + k;
    const bool inside = i < count;
    const float* r = rays + 6 * (inside ? i : first);
    valid[k] = inside ? -1 : 0;
    ray.org_x[k] = r[0];
    ray.org_y[k] = r[1];
    ray.org_z[k] = r[2];
    ray.dir_x[k] = r[3];
    ray.dir_y[k] = r[4];
    ray.dir_z[k] = r[5];
    ray.tnear[k] = 0.0f;
    ray.tfar[k] = tfar;
    ray.time[k] = 0.0f;
    ray.mask[k] = 0xFFFFFFFFu;
    ray.id[k] = static_cast<unsigned>(k);
    ray.flags[k] = 0;
  }
}

RTCRay8& rays_of(RTCRayHit8& packet) { return packet.ray; }
RTCRay8& rays_of(RTCRay8& packet) { return packet; }

// Runs trace(valid, context, packet, first ray, rays in it) over the rays (K, 6) eight at a time, the
// packets shared out among `threads` threads with the GIL released.
template <typename Packet, typename Trace>
void for_each_packet(const float* rays, int64_t count, float tfar, int threads, Trace trace) {
  py::gil_scoped_release unlocked;
  parallel_chunks(count, kPacket * kPacketsPerTask, threads, [&](int64_t first, int64_t last) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(32) Packet packet;
    alignas(32) int valid[kPacket];
    for (int64_t start = first; start < last; start += kPacket) {
      load_packet(rays, start, last, tfar, rays_of(packet), valid);
      trace(valid, &context, packet, start, static_cast<int>(std::min<int64_t>(kPacket, last - start)));
    }
  });
}

std::string device_error(RTCDevice device) {
  switch (rtcGetDeviceError(device)) {
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "this CPU is not supported by Embree (it needs SSE2)";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory building the ray-casting structure";
    default:
      return "Embree failed (error " + std::to_string(static_cast<int>(rtcGetDeviceError(device))) + ")";
  }
}

// A triangle mesh copied into an Embree scene of its own (vertices padded: Embree may read 16 bytes at
// the last one).
struct MeshScene {
  std::vector<float> vertices;
  std::vector<uint32_t> faces;
  RTCScene scene = nullptr;
};

void build_mesh_scene(RTCDevice device, const FloatArray& vertices, const IndexArray& faces, MeshScene* out) {
  if (vertices.ndim() != 2 || vertices.shape(1) != 3) throw std::invalid_argument("vertices must be (N, 3)");
  if (faces.ndim() != 2 || faces.shape(1) != 3) throw std::invalid_argument("faces must be (M, 3)");
  const int64_t num_vertices = vertices.shape(0);
  const uint32_t* index = faces.data();
  for (int64_t i = 0; i < faces.size(); ++i) {
    if (index[i] >= num_vertices) throw std::invalid_argument("a face names a vertex that does not exist");
  }
  out->vertices.assign(vertices.data(), vertices.data() + vertices.size());
  out->vertices.resize(out->vertices.size() + 4, 0.0f);
  out->faces.assign(index, index + faces.size());
  out->scene = rtcNewScene(device);
  rtcSetSceneBuildQuality(out->scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(out->scene, RTC_SCENE_FLAG_ROBUST);  // no ray slips between two triangles of an edge
  if (faces.shape(0) > 0) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, out->vertices.data(), 0,
                               3 * sizeof(float), static_cast<size_t>(num_vertices));
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, out->faces.data(), 0,
                               3 * sizeof(uint32_t), static_cast<size_t>(faces.shape(0)));
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(out->scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(out->scene);
}

class TriangleCaster {
 public:
  TriangleCaster(FloatArray vertices, IndexArray faces) {
    device_ = rtcNewDevice(nullptr);
    if (device_ == nullptr) throw std::runtime_error(device_error(nullptr));
    try {
      build_mesh_scene(device_, vertices, faces, &static_);
    } catch (...) {
      release();
      throw;
    }
    check_device();
  }

  ~TriangleCaster() { release(); }
  TriangleCaster(const TriangleCaster&) = delete;
  TriangleCaster& operator=(const TriangleCaster&) = delete;

  int64_t num_faces() const { return static_cast<int64_t>(static_.faces.size() / 3); }

  // A mesh that instances can show (a person, a car), in its own frame; returns its index.
  int add_shape(FloatArray vertices, IndexArray faces) {
    shapes_.emplace_back();
    try {
      build_mesh_scene(device_, vertices, faces, &shapes_.back());
    } catch (...) {
      if (shapes_.back().scene != nullptr) rtcReleaseScene(shapes_.back().scene);
      shapes_.pop_back();
      throw;
    }
    check_device();
    return static_cast<int>(shapes_.size()) - 1;
  }

  int num_shapes() const { return static_cast<int>(shapes_.size()); }
  int num_instances() const { return active_; }

  // The instances shown from now on: instance i is shape shapes[i] under the rigid transform
  // transforms[i] (4 x 4, row-major, shape frame to world). Replaces the previous ones.
  void set_instances(py::array_t<int32_t, py::array::c_style | py::array::forcecast> shapes,
                     FloatArray transforms) {
    const int64_t count = shapes.size();
    if (transforms.size() != 16 * count) throw std::invalid_argument("give one 4 x 4 transform per instance");
    const int32_t* shape = shapes.data();
    for (int64_t i = 0; i < count; ++i) {
      if (shape[i] < 0 || shape[i] >= num_shapes()) throw std::invalid_argument("an instance names no shape");
    }
    if (top_ == nullptr) {
      top_ = rtcNewScene(device_);
      rtcSetSceneFlags(top_, static_cast<RTCSceneFlags>(RTC_SCENE_FLAG_DYNAMIC | RTC_SCENE_FLAG_ROBUST));
      RTCGeometry world = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);  // geometry 0: the static mesh
      rtcSetGeometryInstancedScene(world, static_.scene);
      const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
      rtcSetGeometryTransform(world, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
      rtcCommitGeometry(world);
      rtcAttachGeometryByID(top_, world, 0);
      rtcReleaseGeometry(world);
    }
    const float* m = transforms.data();
    for (int64_t i = 0; i < count; ++i) {
      if (static_cast<size_t>(i) == instances_.size()) {
        RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcAttachGeometryByID(top_, geometry, static_cast<unsigned>(i + 1));
        instances_.push_back(geometry);
      }
      RTCGeometry geometry = instances_[static_cast<size_t>(i)];
      const float* r = m + 16 * i;  // row-major 4 x 4 -> column-major 3 x 4
      const float columns[12] = {r[0], r[4], r[8], r[1], r[5], r[9], r[2], r[6], r[10], r[3], r[7], r[11]};
      rtcSetGeometryInstancedScene(geometry, shapes_[static_cast<size_t>(shape[i])].scene);
      rtcSetGeometryTransform(geometry, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, columns);
      rtcEnableGeometry(geometry);
      rtcCommitGeometry(geometry);
    }
    for (size_t i = static_cast<size_t>(count); i < instances_.size(); ++i) rtcDisableGeometry(instances_[i]);
    active_ = static_cast<int>(count);
    rtcCommitScene(top_);
    check_device();
  }

  // The first hit of each ray (K, 6) = origin, direction: t_hit (inf: none), face (0xFFFFFFFF: none; a
  // face of the shape for an instance hit), barycentric (u, v), instance (-1: the static mesh or
  // none), written into the given arrays.
  void cast(FloatArray rays, py::array_t<float, py::array::c_style> t_hit,
            py::array_t<uint32_t, py::array::c_style> face, py::array_t<float, py::array::c_style> uv,
            py::array_t<int32_t, py::array::c_style> instance, int threads) const {
    const int64_t count = ray_count(rays);
    if (t_hit.size() != count || face.size() != count || uv.size() != 2 * count || instance.size() != count)
      throw std::invalid_argument("the outputs must have one entry (two for uv) per ray");
    float* t_out = t_hit.mutable_data();
    uint32_t* face_out = face.mutable_data();
    float* uv_out = uv.mutable_data();
    int32_t* instance_out = instance.mutable_data();
    const bool layered = active_ > 0;
    RTCScene scene = layered ? top_ : static_.scene;
    for_each_packet<RTCRayHit8>(rays.data(), count, kInfinity, threads,
                                [&](int* valid, RTCIntersectContext* context, RTCRayHit8& packet,
                                    int64_t start, int size) {
      for (int k = 0; k < kPacket; ++k) {
        packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.primID[k] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect8(valid, scene, context, &packet);
      for (int k = 0; k < size; ++k) {
        const int64_t i = start + k;
        const bool hit = packet.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
        const unsigned which = packet.hit.instID[0][k];
        t_out[i] = hit ? packet.ray.tfar[k] : kInfinity;
        face_out[i] = hit ? packet.hit.primID[k] : RTC_INVALID_GEOMETRY_ID;
        uv_out[2 * i] = hit ? packet.hit.u[k] : 0.0f;
        uv_out[2 * i + 1] = hit ? packet.hit.v[k] : 0.0f;
        instance_out[i] = (hit && layered && which != RTC_INVALID_GEOMETRY_ID && which > 0)
                              ? static_cast<int32_t>(which) - 1
                              : -1;
      }
    });
  }

  // Whether each ray (K, 6) meets a triangle (of the mesh or an instance) with parameter in [0, tfar].
  void occluded(FloatArray rays, float tfar, py::array_t<uint8_t, py::array::c_style> blocked,
                int threads) const {
    const int64_t count = ray_count(rays);
    if (blocked.size() != count) throw std::invalid_argument("the output must have one entry per ray");
    uint8_t* out = blocked.mutable_data();
    RTCScene scene = active_ > 0 ? top_ : static_.scene;
    for_each_packet<RTCRay8>(rays.data(), count, tfar, threads,
                             [&](int* valid, RTCIntersectContext* context, RTCRay8& packet, int64_t start,
                                 int size) {
      rtcOccluded8(valid, scene, context, &packet);
      for (int k = 0; k < size; ++k) {
        out[start + k] = packet.tfar[k] < 0.0f ? 1 : 0;  // Embree marks an occluded ray with tfar = -inf
      }
    });
  }

 private:
  static int64_t ray_count(const FloatArray& rays) {
    if (rays.ndim() < 1 || rays.shape(rays.ndim() - 1) != 6) throw std::invalid_argument("rays must be (..., 6)");
    return rays.size() / 6;
  }

  void check_device() {
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) {
      const std::string message = device_error(device_);
      throw std::runtime_error(message);
    }
  }

  void release() {
    for (RTCGeometry geometry : instances_) rtcReleaseGeometry(geometry);
    instances_.clear();
    if (top_ != nullptr) rtcReleaseScene(top_);
    for (MeshScene& shape : shapes_)
      if (shape.scene != nullptr) rtcReleaseScene(shape.scene);
    shapes_.clear();
    if (static_.scene != nullptr) rtcReleaseScene(static_.scene);
    if (device_ != nullptr) rtcReleaseDevice(device_);
    top_ = nullptr;
    static_.scene = nullptr;
    device_ = nullptr;
  }

  RTCDevice device_ = nullptr;
  MeshScene static_;
  std::vector<MeshScene> shapes_;
  RTCScene top_ = nullptr;  // the static mesh (geometry 0) and the instances (1, 2, ...), once there are any
  std::vector<RTCGeometry> instances_;
  int active_ = 0;
};

}  // namespace

PYBIND11_MODULE(_raycast, m) {
  m.doc() = "Packet ray casting against a triangle mesh (Embree 3); see navverse.sim.raycast.";
  py::class_<TriangleCaster>(m, "TriangleCaster")
      .def(py::init<FloatArray, IndexArray>(), py::arg("vertices"), py::arg("faces"))
      .def_property_readonly("num_faces", &TriangleCaster::num_faces)
      .def_property_readonly("num_shapes", &TriangleCaster::num_shapes)
      .def_property_readonly("num_instances", &TriangleCaster::num_instances)
      .def("add_shape", &TriangleCaster::add_shape, py::arg("vertices"), py::arg("faces"))
      .def("set_instances", &TriangleCaster::set_instances, py::arg("shapes"), py::arg("transforms"))
      .def("cast", &TriangleCaster::cast, py::arg("rays"), py::arg("t_hit"), py::arg("face"), py::arg("uv"),
           py::arg("instance"), py::arg("threads"))
      .def("occluded", &TriangleCaster::occluded, py::arg("rays"), py::arg("tfar"), py::arg("blocked"),
           py::arg("threads"));
}
