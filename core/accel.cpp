#include "core/accel.h"

#include <embree3/rtcore.h>

#include <stdexcept>
#include <string>

namespace penumbra {

namespace {

// Embree reports errors through a callback (rtcSetDeviceErrorFunction), as its minimal tutorial
// shows. Exceptions must not cross Embree's C interface, so the callback only records the
// message and the caller throws once the failing call has returned.
void recordEmbreeError(void* userPtr, RTCError code, const char* message) {
    if (code == RTC_ERROR_NONE)
        return;
    *static_cast<std::string*>(userPtr) =
        "Embree error " + std::to_string(code) + ": " + (message ? message : "");
}

RTCRay toRtcRay(const Ray& ray) {
    RTCRay r;
    r.org_x = ray.o.x;
    r.org_y = ray.o.y;
    r.org_z = ray.o.z;
    r.tnear = 0.0f;
    r.dir_x = ray.d.x;
    r.dir_y = ray.d.y;
    r.dir_z = ray.d.z;
    r.time = 0.0f;
    r.tfar = ray.tMax;
    r.mask = 0xFFFFFFFFu;
    r.id = 0;
    r.flags = 0;
    return r;
}

}  // namespace

struct Accel::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::string lastError;
};

Accel::Accel(std::span<const Mesh> meshes) : impl_(std::make_unique<Impl>()) {
    impl_->device = rtcNewDevice(nullptr);
    if (!impl_->device) {
        throw std::runtime_error("Embree: cannot create a device (error " +
                                 std::to_string(rtcGetDeviceError(nullptr)) + ")");
    }
    rtcSetDeviceErrorFunction(impl_->device, recordEmbreeError, &impl_->lastError);
    impl_->scene = rtcNewScene(impl_->device);
    // Robust traversal: no missed hits on shared edges, at a small cost (Embree docs,
    // RTC_SCENE_FLAG_ROBUST); high build quality since the scene is built once per render.
    rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
    for (size_t i = 0; i < meshes.size(); ++i) {
        const Mesh& mesh = meshes[i];
        RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree may read 16 bytes past the last vertex with SSE loads; shared buffers need that
        // padding (rtcSetSharedGeometryBuffer docs), so the vertices are copied into Embree's
        // own buffer, while the index buffer (read exactly) is shared.
        auto* vertices = static_cast<Vec3*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                    sizeof(Vec3), mesh.positions.size()));
        std::copy(mesh.positions.begin(), mesh.positions.end(), vertices);
        rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                   mesh.triangles.data(), 0, sizeof(glm::uvec3),
                                   mesh.triangles.size());
        rtcCommitGeometry(geometry);
        rtcAttachGeometryByID(impl_->scene, geometry, static_cast<unsigned>(i));
        rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(impl_->scene);
    if (!impl_->lastError.empty())
        throw std::runtime_error(impl_->lastError);
}

Accel::~Accel() {
    if (impl_->scene)
        rtcReleaseScene(impl_->scene);
    if (impl_->device)
        rtcReleaseDevice(impl_->device);
}

std::optional<RawHit> Accel::intersect(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rayHit;
    rayHit.ray = toRtcRay(ray);
    rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &context, &rayHit);
    if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return std::nullopt;
    return RawHit{rayHit.hit.geomID, rayHit.hit.primID, rayHit.hit.u, rayHit.hit.v,
                  rayHit.ray.tfar};
}

bool Accel::occluded(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r = toRtcRay(ray);
    rtcOccluded1(impl_->scene, &context, &r);
    // Embree sets tfar to -inf when an occluder is found.
    return r.tfar < 0.0f;
}

}  // namespace penumbra
