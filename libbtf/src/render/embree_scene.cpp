#include "btf/render/embree_scene.h"

#include <embree3/rtcore.h>

#include <cstring>
#include <limits>
#include <string>

#include "btf/core/error.h"

namespace btf::render {
namespace {

const char* errorName(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "unknown error";
  }
}

// Embree calls this on its own errors; the message is kept and thrown after the call that failed
// returns (throwing through Embree's C frames would not be safe).
void recordError(void* user, RTCError code, const char* message) {
  auto* last = static_cast<std::string*>(user);
  if (last->empty()) *last = std::string("Embree: ") + errorName(code) + (message ? std::string(": ") + message : "");
}

}  // namespace

struct EmbreeScene::Handles {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::string error;

  void check(const char* what) {
    if (!error.empty()) {
      const std::string message = error + " (" + what + ")";
      error.clear();
      throw Error(message);
    }
  }
  ~Handles() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

EmbreeScene::EmbreeScene(const std::vector<const TriangleMesh*>& meshes) : handles_(std::make_unique<Handles>()) {
  Handles& h = *handles_;
  h.device = rtcNewDevice(nullptr);
  if (!h.device) throw Error(std::string("Embree: cannot create a device: ") + errorName(rtcGetDeviceError(nullptr)));
  rtcSetDeviceErrorFunction(h.device, recordError, &h.error);
  h.scene = rtcNewScene(h.device);
  h.check("creating the scene");
  rtcSetSceneBuildQuality(h.scene, RTC_BUILD_QUALITY_HIGH);
  // Robust traversal: rays that graze shared edges of a watertight mesh do not slip through.
  rtcSetSceneFlags(h.scene, RTC_SCENE_FLAG_ROBUST);

  constexpr float kInf = std::numeric_limits<float>::infinity();
  bounds_min_ = glm::vec3(kInf);
  bounds_max_ = glm::vec3(-kInf);
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const TriangleMesh& mesh = *meshes[m];
    RTCGeometry geometry = rtcNewGeometry(h.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    h.check("creating a triangle geometry");
    // Embree allocates (and pads) the buffers itself; the data is copied in.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh.triangles.size()));
    if (!vertices || !indices) {
      rtcReleaseGeometry(geometry);
      h.check(mesh.name.c_str());
      throw Error("Embree: cannot allocate the buffers of " + mesh.name);
    }
    std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
    std::memcpy(indices, mesh.triangles.data(), mesh.triangles.size() * sizeof(glm::uvec3));
    // Over the vertices of triangles only: a vertex no triangle uses (one of a dropped triangle,
    // possibly infinite, or a stray point of the file) is not part of the scene, and an infinite
    // bound would make the scene's ray offsets and environment power infinite.
    for (const glm::uvec3& t : mesh.triangles)
      for (int k = 0; k < 3; ++k) {
        bounds_min_ = glm::min(bounds_min_, mesh.positions[t[k]]);
        bounds_max_ = glm::max(bounds_max_, mesh.positions[t[k]]);
      }
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(h.scene, geometry, unsigned(m));
    rtcReleaseGeometry(geometry);
    h.check(mesh.name.c_str());
  }
  rtcCommitScene(h.scene);
  h.check("building the BVH");
}

EmbreeScene::~EmbreeScene() = default;

bool EmbreeScene::intersect(const Ray& ray, RayHit& hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = ray.origin.x;
  rh.ray.org_y = ray.origin.y;
  rh.ray.org_z = ray.origin.z;
  rh.ray.dir_x = ray.direction.x;
  rh.ray.dir_y = ray.direction.y;
  rh.ray.dir_z = ray.direction.z;
  rh.ray.tnear = ray.tmin;
  rh.ray.tfar = ray.tmax;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(handles_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit.t = rh.ray.tfar;
  hit.mesh = rh.hit.geomID;
  hit.triangle = rh.hit.primID;
  hit.barycentric = {rh.hit.u, rh.hit.v};
  return true;
}

bool EmbreeScene::occluded(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r;
  r.org_x = ray.origin.x;
  r.org_y = ray.origin.y;
  r.org_z = ray.origin.z;
  r.dir_x = ray.direction.x;
  r.dir_y = ray.direction.y;
  r.dir_z = ray.direction.z;
  r.tnear = ray.tmin;
  r.tfar = ray.tmax;
  r.time = 0.0f;
  r.mask = 0xFFFFFFFFu;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(handles_->scene, &context, &r);
  // Embree marks an occluded ray by setting tfar to -inf.
  return r.tfar < 0.0f;
}

}  // namespace btf::render
