#include "hrpp/reference/embree_ref.h"

#include <embree3/rtcore.h>

#include <chrono>
#include <stdexcept>

namespace hrpp {

struct EmbreeScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::string config;
  bool robust = true;
  bool high_quality = true;
  std::string error;
};

namespace {
void on_error(void* user, RTCError code, const char* str) {
  *static_cast<std::string*>(user) =
      "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (str ? str : "");
}

void to_rtc(const Ray& r, RTCRay* out) {
  // Embree asserts (aborts the process) on an origin outside its range: refuse it here instead.
  if (!(max_abs(r.org) < kEmbreeLarge))
    throw std::invalid_argument("Embree: ray origin outside Embree's range (|x| < 1.844e18)");
  out->org_x = r.org.x;
  out->org_y = r.org.y;
  out->org_z = r.org.z;
  out->dir_x = r.dir.x;
  out->dir_y = r.dir.y;
  out->dir_z = r.dir.z;
  out->tnear = r.tnear;
  out->tfar = r.tfar;
  out->time = 0.f;
  out->mask = 0xFFFFFFFFu;
  out->id = 0;
  out->flags = 0;
}
}  // namespace

EmbreeScene::EmbreeScene(const std::vector<Triangle>& tris, const std::string& device_config,
                         bool robust, bool high_quality)
    : impl_(std::make_unique<Impl>()) {
  impl_->config = device_config;
  impl_->robust = robust;
  impl_->high_quality = high_quality;
  impl_->device = rtcNewDevice(device_config.c_str());
  if (!impl_->device)
    throw std::runtime_error("Embree: cannot create device with config '" + device_config + "'");
  rtcSetDeviceErrorFunction(impl_->device, on_error, &impl_->error);
  auto t0 = std::chrono::steady_clock::now();
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->scene, robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
  if (high_quality) rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * tris.size()));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tris.size()));
  if (!v || !idx) throw std::runtime_error("Embree: buffer allocation failed: " + impl_->error);
  for (size_t i = 0; i < tris.size(); ++i) {
    const Vec3* p[3] = {&tris[i].v0, &tris[i].v1, &tris[i].v2};
    for (int k = 0; k < 3; ++k) {
      v[9 * i + 3 * k + 0] = p[k]->x;
      v[9 * i + 3 * k + 1] = p[k]->y;
      v[9 * i + 3 * k + 2] = p[k]->z;
      idx[3 * i + k] = static_cast<unsigned>(3 * i + k);
    }
  }
  rtcCommitGeometry(g);
  rtcAttachGeometry(impl_->scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(impl_->scene);
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!impl_->error.empty()) throw std::runtime_error(impl_->error);
}

EmbreeScene::~EmbreeScene() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

Hit EmbreeScene::intersect(const Ray& r) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  to_rtc(r, &rh.ray);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &ctx, &rh);
  Hit h;
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
    h.t = rh.ray.tfar;
    h.u = rh.hit.u;
    h.v = rh.hit.v;
    h.prim = rh.hit.primID;
  }
  return h;
}

bool EmbreeScene::occluded(const Ray& r) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay ray;
  to_rtc(r, &ray);
  rtcOccluded1(impl_->scene, &ctx, &ray);
  return ray.tfar == -kInf;
}

std::string EmbreeScene::description() const {
  const long ver = rtcGetDeviceProperty(impl_->device, RTC_DEVICE_PROPERTY_VERSION);
  return "Embree " + std::to_string(ver / 10000) + "." + std::to_string(ver / 100 % 100) + "." +
         std::to_string(ver % 100) + " (" + impl_->config + ", " +
         (impl_->robust ? "RTC_SCENE_FLAG_ROBUST" : "default flags") +
         (impl_->high_quality ? ", RTC_BUILD_QUALITY_HIGH" : ", default build quality (medium)") +
         ", rtcIntersect1/rtcOccluded1)";
}

}  // namespace hrpp
