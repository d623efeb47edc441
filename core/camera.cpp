#include "core/camera.h"

#include "core/errors.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace penumbra {

Camera::Camera(const CameraDesc& desc, int width, int height)
    : desc_(desc), width_(width), height_(height) {
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    halfHeight_ =
        desc.projection == ProjectionType::Perspective ? std::tan(0.5f * desc.yfov) : desc.ymag;
    halfWidth_ = halfHeight_ * aspect;
}

Ray Camera::generateRay(Vec2 filmPosition) const {
    // Normalised device coordinates in [-1, 1], +y up.
    const float x = 2.0f * filmPosition.x / static_cast<float>(width_) - 1.0f;
    const float y = 1.0f - 2.0f * filmPosition.y / static_cast<float>(height_);
    const Mat4& toWorld = desc_.cameraToWorld;
    Ray ray;
    if (desc_.projection == ProjectionType::Perspective) {
        const Vec3 dCamera = glm::normalize(Vec3(x * halfWidth_, y * halfHeight_, -1.0f));
        ray.o = Vec3(toWorld[3]);
        ray.d = glm::normalize(Mat3(toWorld) * dCamera);
        // Start on the near plane, as glTF's projection clips there.
        ray.o += ray.d * (desc_.znear / -dCamera.z);
    } else {
        ray.o = Vec3(toWorld * Vec4(x * halfWidth_, y * halfHeight_, -desc_.znear, 1.0f));
        ray.d = glm::normalize(Mat3(toWorld) * Vec3(0.0f, 0.0f, -1.0f));
    }
    return ray;
}

CameraDesc chooseCamera(std::span<const CameraDesc> cameras, const std::string& name,
                        const Bounds3& sceneBounds) {
    if (!name.empty()) {
        std::string names;
        for (const CameraDesc& camera : cameras) {
            if (camera.name == name)
                return camera;
            names += (names.empty() ? "" : ", ") + ("'" + camera.name + "'");
        }
        throw UsageError("--camera: the scene has no camera named '" + name + "'" +
                         (names.empty() ? " (it has no cameras)" : "; cameras: " + names));
    }
    if (!cameras.empty())
        return cameras.front();

    CameraDesc framing;
    framing.name = "framing camera";
    framing.yfov = glm::radians(45.0f);
    const Vec3 center = sceneBounds.empty() ? Vec3(0.0f) : sceneBounds.center();
    const float radius = sceneBounds.empty() ? 1.0f : glm::max(sceneBounds.boundingRadius(), 1e-6f);
    // Distance at which the bounding sphere fits the vertical field of view.
    const float distance = radius / std::sin(0.5f * framing.yfov);
    const Vec3 direction = glm::normalize(Vec3(0.0f, 0.25f, 1.0f));
    const Vec3 eye = center + direction * distance;
    framing.cameraToWorld = glm::inverse(glm::lookAt(eye, center, Vec3(0.0f, 1.0f, 0.0f)));
    framing.znear = 1e-4f * distance;
    return framing;
}

IVec2 chooseImageSize(const CameraDesc& camera, int width, int height) {
    float aspect = camera.aspectRatio > 0.0f ? camera.aspectRatio : 4.0f / 3.0f;
    if (camera.projection == ProjectionType::Orthographic && camera.aspectRatio <= 0.0f &&
        camera.ymag > 0.0f) {
        aspect = camera.xmag / camera.ymag;
    }
    if (width > 0 && height > 0)
        return {width, height};
    if (width > 0)
        return {width, glm::max(1, static_cast<int>(std::lround(width / aspect)))};
    if (height > 0)
        return {glm::max(1, static_cast<int>(std::lround(height * aspect))), height};
    constexpr int kDefaultWidth = 640;
    return {kDefaultWidth, glm::max(1, static_cast<int>(std::lround(kDefaultWidth / aspect)))};
}

}  // namespace penumbra
