// nanoflann (Debian's libnanoflann-dev, header-only) is seen by this file only.
#include "caustics/photon_kdtree.h"

#include <nanoflann.hpp>

#include <cmath>

namespace penumbra {

namespace {

// The normal test: cos of the largest angle between photon and receiver normals (25.8 degrees).
constexpr float kMinNormalCosine = 0.9f;
// The disc test: the largest distance from the receiver's tangent plane, as a fraction of the
// photon's distance (curved surfaces), plus a fraction of the search radius (rounding).
constexpr float kDiscSlope = 0.1f;
constexpr float kDiscThickness = 1e-4f;
// Photons per leaf of the tree.
constexpr size_t kLeafSize = 16;

// The photons as nanoflann's dataset ("DatasetAdaptor" in nanoflann's README).
struct PhotonCloud {
    std::vector<Photon> photons;

    size_t kdtree_get_point_count() const { return photons.size(); }
    float kdtree_get_pt(uint32_t index, size_t dim) const { return photons[index].p[dim]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const {
        return false;
    }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PhotonCloud>,
                                                   PhotonCloud, 3, uint32_t>;

// The leak tests of photon_kdtree.h.
struct LeakTest {
    Vec3 x, n;
    float thickness;

    bool passes(const Photon& p, float dist2) const {
        return glm::dot(p.n, n) >= kMinNormalCosine &&
               std::abs(glm::dot(p.p - x, n)) <= kDiscSlope * std::sqrt(dist2) + thickness;
    }
};

// nanoflann's result-set interface (the shape of its KNNResultSet): the k nearest photons that
// pass the leak tests, no farther than the maximum radius.
class NearestPassing {
  public:
    NearestPassing(const PhotonCloud& cloud, const LeakTest& test, size_t k, float maxRadius,
                   std::vector<PhotonNeighbour>& out)
        : cloud_(cloud), test_(test), k_(k), maxDist2_(sqr(maxRadius)), out_(out) {
        out_.clear();
        out_.reserve(k_);
    }

    size_t size() const { return out_.size(); }
    bool full() const { return out_.size() == k_; }
    float worstDist() const { return full() ? out_.back().dist2 : maxDist2_; }

    bool addPoint(float dist2, uint32_t index) {
        if (!test_.passes(cloud_.photons[index], dist2))
            return true;
        // Insertion into the sorted list, dropping the farthest when it is full.
        if (full())
            out_.pop_back();
        out_.push_back(PhotonNeighbour{index, dist2});
        for (size_t i = out_.size() - 1; i > 0 && out_[i - 1].dist2 > dist2; --i)
            std::swap(out_[i - 1], out_[i]);
        return true;
    }

  private:
    const PhotonCloud& cloud_;
    const LeakTest& test_;
    size_t k_;
    float maxDist2_;
    std::vector<PhotonNeighbour>& out_;
};

// The same interface for a radius search: every passing photon within the radius.
class WithinPassing {
  public:
    WithinPassing(const PhotonCloud& cloud, const LeakTest& test, float radius,
                  std::vector<PhotonNeighbour>& out)
        : cloud_(cloud), test_(test), dist2_(sqr(radius)), out_(out) {
        out_.clear();
    }

    size_t size() const { return out_.size(); }
    bool full() const { return true; }
    float worstDist() const { return dist2_; }

    bool addPoint(float dist2, uint32_t index) {
        if (test_.passes(cloud_.photons[index], dist2))
            out_.push_back(PhotonNeighbour{index, dist2});
        return true;
    }

  private:
    const PhotonCloud& cloud_;
    const LeakTest& test_;
    float dist2_;
    std::vector<PhotonNeighbour>& out_;
};

}  // namespace

struct PhotonKdTree::Data {
    PhotonCloud cloud;
    std::unique_ptr<KdTree> tree;
};

PhotonKdTree::PhotonKdTree(std::vector<Photon> photons) : data_(std::make_unique<Data>()) {
    data_->cloud.photons = std::move(photons);
    data_->tree = std::make_unique<KdTree>(3, data_->cloud,
                                           nanoflann::KDTreeSingleIndexAdaptorParams(kLeafSize));
}

PhotonKdTree::PhotonKdTree(PhotonKdTree&&) noexcept = default;
PhotonKdTree& PhotonKdTree::operator=(PhotonKdTree&&) noexcept = default;
PhotonKdTree::~PhotonKdTree() = default;

std::span<const Photon> PhotonKdTree::photons() const {
    return data_->cloud.photons;
}

void PhotonKdTree::nearest(const Vec3& x, const Vec3& n, int k, float maxRadius,
                           std::vector<PhotonNeighbour>& out) const {
    const LeakTest test{x, n, kDiscThickness * maxRadius};
    NearestPassing result(data_->cloud, test, static_cast<size_t>(k), maxRadius, out);
    if (data_->cloud.photons.empty() || k < 1)
        return;
    const float query[3] = {x.x, x.y, x.z};
    data_->tree->findNeighbors(result, query, nanoflann::SearchParams());
}

void PhotonKdTree::within(const Vec3& x, const Vec3& n, float radius,
                          std::vector<PhotonNeighbour>& out) const {
    const LeakTest test{x, n, kDiscThickness * radius};
    WithinPassing result(data_->cloud, test, radius, out);
    if (data_->cloud.photons.empty())
        return;
    const float query[3] = {x.x, x.y, x.z};
    data_->tree->findNeighbors(result, query, nanoflann::SearchParams());
}

size_t PhotonKdTree::memoryBytes() const {
    return data_->cloud.photons.capacity() * sizeof(Photon) + data_->tree->usedMemory(*data_->tree);
}

}  // namespace penumbra
