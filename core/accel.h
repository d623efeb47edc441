// Ray-triangle intersection for a set of world-space meshes, behind an interface that hides
// the ray-tracing library (Embree 3): accel.cpp is the only file that includes Embree.
#pragma once

#include "core/ray.h"
#include "core/scene_description.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <span>

namespace penumbra {

struct RawHit {
    uint32_t mesh = 0;         // index into the meshes given to the constructor
    uint32_t triangle = 0;     // index into that mesh's triangles
    float u = 0.0f, v = 0.0f;  // barycentrics of vertices 1 and 2
    float t = 0.0f;
};

class Accel {
  public:
    // Builds the acceleration structure once; the meshes must outlive the Accel (their
    // vertex and index arrays are shared with the library, not copied).
    explicit Accel(std::span<const Mesh> meshes);
    ~Accel();
    Accel(const Accel&) = delete;
    Accel& operator=(const Accel&) = delete;

    // Closest hit with t in (0, ray.tMax).
    std::optional<RawHit> intersect(const Ray& ray) const;
    // Whether anything is hit with t in (0, ray.tMax).
    bool occluded(const Ray& ray) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
