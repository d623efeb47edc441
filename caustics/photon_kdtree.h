// A kd-tree over photons (nanoflann, seen by photon_kdtree.cpp only) with the searches the
// caustic estimates need: the k nearest photons (CausticMap) and every photon within a radius
// (ProgressiveCaustics). Both apply the same leak tests (Jensen 2001, "Realistic Image Synthesis
// Using Photon Mapping", chapter 7: a disc instead of a sphere): a photon counts only if its
// normal (on the side it arrived from) is within 25.8 degrees of the receiver's normal on the
// viewer's side (dot > 0.9), and it lies within 0.1 d + 1e-4 r of the receiver's tangent plane,
// d being its distance and r the search radius. So photons on the other side of a wall, on a wall
// meeting the receiver at a corner, or on a parallel surface above or below do not count.
#pragma once

#include "caustics/photon_tracer.h"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace penumbra {

struct PhotonNeighbour {
    uint32_t index;  // into photons()
    float dist2;     // squared distance, m²
};

class PhotonKdTree {
  public:
    explicit PhotonKdTree(std::vector<Photon> photons);
    PhotonKdTree(PhotonKdTree&&) noexcept;
    PhotonKdTree& operator=(PhotonKdTree&&) noexcept;
    ~PhotonKdTree();

    std::span<const Photon> photons() const;

    // The k nearest photons to x no farther than maxRadius that pass the leak tests for the
    // receiver normal n (unit, on the viewer's side), by ascending distance. Rejected photons do
    // not count towards k (the tests are part of the search).
    void nearest(const Vec3& x, const Vec3& n, int k, float maxRadius,
                 std::vector<PhotonNeighbour>& out) const;
    // Every photon within `radius` of x that passes the leak tests, in no particular order.
    void within(const Vec3& x, const Vec3& n, float radius,
                std::vector<PhotonNeighbour>& out) const;

    // Photons and tree, bytes.
    size_t memoryBytes() const;

  private:
    struct Data;
    std::unique_ptr<Data> data_;
};

}  // namespace penumbra
