// Cameras: glTF perspective and orthographic projections, generating primary rays.
#pragma once

#include "core/math.h"
#include "core/ray.h"
#include "core/scene_description.h"

#include <span>
#include <string>

namespace penumbra {

class Camera {
  public:
    // Film of width x height pixels. The glTF camera looks down its local -Z with +Y up; its
    // field of view (yfov, or ymag) spans the film's height, and the film's aspect ratio is
    // the image's, whatever the camera's aspectRatio says (as glTF viewers do).
    Camera(const CameraDesc& desc, int width, int height);

    // Ray through the film position (in pixels, (0,0) = top-left corner of the image).
    Ray generateRay(Vec2 filmPosition) const;

    const CameraDesc& description() const { return desc_; }

  private:
    CameraDesc desc_;
    int width_, height_;
    float halfHeight_;  // tan(yfov/2) for perspective, ymag for orthographic
    float halfWidth_;
};

// The camera to use: the one named `name` (UsageError listing the names if there is none),
// else the first one, else a perspective camera framing the scene's bounds from the front
// (+Z side, slightly above), with a 45 degree vertical field of view.
CameraDesc chooseCamera(std::span<const CameraDesc> cameras, const std::string& name,
                        const Bounds3& sceneBounds);

// Image size: both given -> as given; one given -> the other from the camera's aspect ratio;
// none -> 640 pixels wide and the camera's aspect ratio (4:3 when it has none).
IVec2 chooseImageSize(const CameraDesc& camera, int width, int height);

}  // namespace penumbra
