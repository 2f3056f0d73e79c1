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

class TriangleCaster {
 public:
  TriangleCaster(FloatArray vertices, IndexArray faces) : vertices_(vertices), faces_(faces) {
    if (vertices_.ndim() != 2 || vertices_.shape(1) != 3) throw std::invalid_argument("vertices must be (N, 3)");
    if (faces_.ndim() != 2 || faces_.shape(1) != 3) throw std::invalid_argument("faces must be (M, 3)");
    const uint32_t* index = faces_.data();
    const int64_t num_vertices = vertices_.shape(0);
    for (int64_t i = 0; i < faces_.size(); ++i) {
      if (index[i] >= num_vertices) throw std::invalid_argument("a face names a vertex that does not exist");
    }
    device_ = rtcNewDevice(nullptr);
    if (device_ == nullptr) throw std::runtime_error(device_error(nullptr));
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);  // no ray slips between two triangles of an edge
    if (faces_.shape(0) > 0) {
      RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      // Embree may read 16 bytes at the last vertex: the shared buffer is padded by one vertex.
      padded_.assign(vertices_.data(), vertices_.data() + vertices_.size());
      padded_.resize(padded_.size() + 4, 0.0f);
      rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, padded_.data(), 0,
                                 3 * sizeof(float), static_cast<size_t>(num_vertices));
      rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, faces_.data(), 0,
                                 3 * sizeof(uint32_t), static_cast<size_t>(faces_.shape(0)));
      rtcCommitGeometry(geometry);
      rtcAttachGeometry(scene_, geometry);
      rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) {
      const std::string message = device_error(device_);
      release();
      throw std::runtime_error(message);
    }
  }

  ~TriangleCaster() { release(); }
  TriangleCaster(const TriangleCaster&) = delete;
  TriangleCaster& operator=(const TriangleCaster&) = delete;

  int64_t num_faces() const { return faces_.shape(0); }

  // The first hit of each ray (K, 6) = origin, direction: t_hit (inf: none), face (0xFFFFFFFF: none),
  // barycentric (u, v), written into the given arrays.
  void cast(FloatArray rays, py::array_t<float, py::array::c_style> t_hit,
            py::array_t<uint32_t, py::array::c_style> face, py::array_t<float, py::array::c_style> uv,
            int threads) const {
    const int64_t count = ray_count(rays);
    if (t_hit.size() != count || face.size() != count || uv.size() != 2 * count)
      throw std::invalid_argument("the outputs must have one entry (two for uv) per ray");
    float* t_out = t_hit.mutable_data();
    uint32_t* face_out = face.mutable_data();
    float* uv_out = uv.mutable_data();
    for_each_packet<RTCRayHit8>(rays.data(), count, kInfinity, threads,
                                [&](int* valid, RTCIntersectContext* context, RTCRayHit8& packet,
                                    int64_t start, int size) {
      for (int k = 0; k < kPacket; ++k) {
        packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.primID[k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect8(valid, scene_, context, &packet);
      for (int k = 0; k < size; ++k) {
        const int64_t i = start + k;
        const bool hit = packet.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
        t_out[i] = hit ? packet.ray.tfar[k] : kInfinity;
        face_out[i] = hit ? packet.hit.primID[k] : RTC_INVALID_GEOMETRY_ID;
        uv_out[2 * i] = hit ? packet.hit.u[k] : 0.0f;
        uv_out[2 * i + 1] = hit ? packet.hit.v[k] : 0.0f;
      }
    });
  }

  // Whether each ray (K, 6) meets a triangle with parameter in [0, tfar], into `blocked` (0 or 1).
  void occluded(FloatArray rays, float tfar, py::array_t<uint8_t, py::array::c_style> blocked,
                int threads) const {
    const int64_t count = ray_count(rays);
    if (blocked.size() != count) throw std::invalid_argument("the output must have one entry per ray");
    uint8_t* out = blocked.mutable_data();
    for_each_packet<RTCRay8>(rays.data(), count, tfar, threads,
                             [&](int* valid, RTCIntersectContext* context, RTCRay8& packet, int64_t start,
                                 int size) {
      rtcOccluded8(valid, scene_, context, &packet);
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

  void release() {
    if (scene_ != nullptr) rtcReleaseScene(scene_);
    if (device_ != nullptr) rtcReleaseDevice(device_);
    scene_ = nullptr;
    device_ = nullptr;
  }

  FloatArray vertices_;
  IndexArray faces_;
  std::vector<float> padded_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

}  // namespace

PYBIND11_MODULE(_raycast, m) {
  m.doc() = "Packet ray casting against a triangle mesh (Embree 3); see navverse.sim.raycast.";
  py::class_<TriangleCaster>(m, "TriangleCaster")
      .def(py::init<FloatArray, IndexArray>(), py::arg("vertices"), py::arg("faces"))
      .def_property_readonly("num_faces", &TriangleCaster::num_faces)
      .def("cast", &TriangleCaster::cast, py::arg("rays"), py::arg("t_hit"), py::arg("face"), py::arg("uv"),
           py::arg("threads"))
      .def("occluded", &TriangleCaster::occluded, py::arg("rays"), py::arg("tfar"), py::arg("blocked"),
           py::arg("threads"));
}
