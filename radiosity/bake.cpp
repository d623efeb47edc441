#include "radiosity/bake.h"

#include "core/progress.h"
#include "core/scene.h"
#include "core/version.h"
#include "radiosity/radiosity_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

namespace penumbra {

namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

// A radiance sample for the automatic exposure: the largest channel at a vertex of a triangle and
// a third of the triangle's area (m²).
struct WeightedRadiance {
    float value = 0.0f;
    double weight = 0.0;
};

// The value below which `quantile` of the total weight lies (0 for no samples).
float weightedQuantile(std::vector<WeightedRadiance> samples, double quantile) {
    if (samples.empty())
        return 0.0f;
    std::sort(
        samples.begin(), samples.end(),
        [](const WeightedRadiance& a, const WeightedRadiance& b) { return a.value < b.value; });
    double total = 0.0;
    for (const WeightedRadiance& s : samples)
        total += s.weight;
    double below = 0.0;
    for (const WeightedRadiance& s : samples) {
        below += s.weight;
        if (below >= quantile * total)
            return s.value;
    }
    return samples.back().value;
}

// A point of a leaf's boundary: a corner or a vertex inside one of its edges, on edge `edge`
// (from corner `edge` to the next) at parameter s in [0, 1) along it, at barycentrics b of the
// scene triangle.
struct RingPoint {
    uint32_t vertex;
    Vec3 b;
    size_t edge;
    float s;
};

// Whether two values at a vertex are written as one (kSameBakedRadiance).
bool sameRadiance(const Color& a, const Color& b) {
    return maxComponent(glm::abs(a - b)) <=
           kSameBakedRadiance * std::max(maxComponent(a), maxComponent(b));
}

// A barycentric coordinate this close to 0 puts a point on the scene triangle's edge.
constexpr float kOnSceneEdge = 1e-6f;
// Points closer than this along a leaf's edge (as a fraction of it) are one: a vertex of the
// leaf and the same point cut from the triangle beside, whose float barycentrics differ in the
// last bits.
constexpr float kSamePoint = 1e-6f;

// The vertices of a scene mesh's leaves that lie on the edges of its scene triangles, by edge. A
// leaf edge on a scene triangle's edge takes the ones inside it into its own boundary, so that no
// vertex of the triangle beside (cut along other shadow or contact lines, or refined otherwise)
// lies inside one of its edges: a T-junction, which viewers show as a crack. (Inside one scene
// triangle the polygon mesh's faces share their edges, and leafBoundary() has them already.)
class SceneEdgePoints {
  public:
    explicit SceneEdgePoints(const Mesh& source) : source_(source) {}

    // The scene edge opposite corner j of `triangle`: its end points, ordered.
    struct Edge {
        Vec3 a, b;
        bool operator<(const Edge& o) const {
            return std::tie(a.x, a.y, a.z, b.x, b.y, b.z) <
                   std::tie(o.a.x, o.a.y, o.a.z, o.b.x, o.b.y, o.b.z);
        }
        double parameter(const Vec3& p) const {
            const glm::dvec3 d = glm::dvec3(b) - glm::dvec3(a);
            return glm::dot(glm::dvec3(p) - glm::dvec3(a), d) / glm::dot(d, d);
        }
    };
    Edge edge(uint32_t triangle, int j) const {
        const glm::uvec3& t = source_.triangles[triangle];
        Vec3 a = source_.positions[t[(j + 1) % 3]], b = source_.positions[t[(j + 2) % 3]];
        if (std::tie(b.x, b.y, b.z) < std::tie(a.x, a.y, a.z))
            std::swap(a, b);
        return {a, b};
    }

    // Registers the points of a leaf's ring that lie inside an edge of its scene triangle.
    void add(const RadiosityMesh& mesh, uint32_t triangle, const std::vector<RingPoint>& ring) {
        for (const RingPoint& p : ring) {
            for (int j = 0; j < 3; ++j) {
                if (std::abs(p.b[j]) > kOnSceneEdge || p.b[(j + 1) % 3] <= kOnSceneEdge ||
                    p.b[(j + 2) % 3] <= kOnSceneEdge)
                    continue;
                const Edge e = edge(triangle, j);
                points_[e].push_back({e.parameter(mesh.position(p.vertex)), p.vertex});
            }
        }
    }

    // The registered points inside the leaf edge from vertex `from` to vertex `to`, which lies on
    // edge j of `triangle`, as (parameter along the leaf edge, vertex).
    std::vector<std::pair<float, uint32_t>> inside(const RadiosityMesh& mesh, uint32_t triangle,
                                                   int j, uint32_t from, uint32_t to) const {
        std::vector<std::pair<float, uint32_t>> found;
        const Edge e = edge(triangle, j);
        const auto it = points_.find(e);
        if (it == points_.end())
            return found;
        const double t0 = e.parameter(mesh.position(from)), t1 = e.parameter(mesh.position(to));
        for (const auto& [t, v] : it->second) {
            const float s = float((t - t0) / (t1 - t0));
            if (s > kSamePoint && s < 1.0f - kSamePoint)
                found.push_back({s, v});
        }
        return found;
    }

  private:
    const Mesh& source_;
    std::map<Edge, std::vector<std::pair<double, uint32_t>>> points_;
};

// Builds the glTF mesh of one scene mesh, leaf by leaf, with the radiance (not yet exposed) of
// every output vertex.
class MeshBaker {
  public:
    MeshBaker(const Scene& scene, const RadiosityMesh& mesh, uint32_t sceneMesh,
              const LeafCornerRadiance& cornerRadiance)
        : mesh_(mesh),
          source_(scene.meshes()[sceneMesh]),
          cornerRadiance_(cornerRadiance),
          edgePoints_(source_) {
        const Material& material = scene.materials()[size_t(source_.material)];
        data_.name = source_.name;
        data_.material =
            material.name.empty() ? "material " + std::to_string(source_.material) : material.name;
        data_.doubleSided = material.doubleSided;
    }

    // Before addLeaf(): the leaf's points on its scene triangle's edges, for the leaves beside.
    void registerEdgePoints(int element) {
        edgePoints_.add(mesh_, mesh_.sceneTriangle(element), ring(element));
    }

    void addLeaf(int element, std::vector<WeightedRadiance>& lit,
                 std::vector<WeightedRadiance>& emissive) {
        const std::array<Color, 3> corner = {
            cornerRadiance_(element, 0), cornerRadiance_(element, 1), cornerRadiance_(element, 2)};
        // The field is linear over a leaf: a point on an edge takes the mix of its corners.
        std::vector<uint32_t> outer;
        for (const RingPoint& p : withEdgePoints(element)) {
            const Color value = glm::mix(corner[p.edge], corner[(p.edge + 1) % 3], p.s);
            outer.push_back(vertex(p.vertex, value, element, p.b));
        }

        const size_t firstTriangle = data_.indices.size();
        if (outer.size() == 3) {
            data_.indices.insert(data_.indices.end(), outer.begin(), outer.end());
        } else {
            // Fan from the centroid, whose value is the linear field's there.
            const std::array<Vec3, 3>& cornerB = mesh_.barycentrics(element);
            const uint32_t centre =
                newVertex(mesh_.centroid(element), (corner[0] + corner[1] + corner[2]) / 3.0f,
                          element, (cornerB[0] + cornerB[1] + cornerB[2]) / 3.0f);
            for (size_t i = 0; i < outer.size(); ++i)
                data_.indices.insert(data_.indices.end(),
                                     {centre, outer[i], outer[(i + 1) % outer.size()]});
        }

        // Samples for the automatic exposure.
        std::vector<WeightedRadiance>& samples =
            maxComponent(mesh_.Le(element)) > 0.0f ? emissive : lit;
        for (size_t i = firstTriangle; i < data_.indices.size(); i += 3) {
            const Vec3& p0 = data_.positions[data_.indices[i]];
            const double area =
                0.5 * glm::length(glm::cross(data_.positions[data_.indices[i + 1]] - p0,
                                             data_.positions[data_.indices[i + 2]] - p0));
            for (size_t k = 0; k < 3; ++k)
                samples.push_back({maxComponent(radiance_[data_.indices[i + k]]), area / 3.0});
        }
    }

    // The mesh with colours = radiance x scale clamped to [0, 1], and the radiance itself.
    GltfMeshData finish(float scale) {
        GltfAttribute radiance{kRadianceAttribute, 3, {}};
        data_.colors.reserve(3 * radiance_.size());
        radiance.values.reserve(3 * radiance_.size());
        for (const Color& L : radiance_) {
            const Color c = glm::clamp(L * scale, 0.0f, 1.0f);
            data_.colors.insert(data_.colors.end(), {c.r, c.g, c.b});
            radiance.values.insert(radiance.values.end(), {L.r, L.g, L.b});
        }
        data_.customAttributes.push_back(std::move(radiance));
        return std::move(data_);
    }

  private:
    // The leaf's boundary (RadiosityMesh::leafBoundary()) with each point's edge, parameter and
    // barycentrics: the corners' are exact; a T-vertex lies on the edge from the last corner
    // passed to the next one.
    std::vector<RingPoint> ring(int element) const {
        const std::array<uint32_t, 3>& corners = mesh_.vertices(element);
        const std::array<Vec3, 3>& cornerB = mesh_.barycentrics(element);
        std::vector<RingPoint> points;
        int corner = -1;
        for (const uint32_t v : mesh_.leafBoundary(element)) {
            if (corner < 2 && v == corners[size_t(corner + 1)]) {
                ++corner;
                points.push_back({v, cornerB[size_t(corner)], size_t(corner), 0.0f});
                continue;
            }
            const size_t from = size_t(corner), to = (from + 1) % 3;
            const Vec3& p0 = mesh_.position(corners[from]);
            const float s =
                glm::length(mesh_.position(v) - p0) / glm::length(mesh_.position(corners[to]) - p0);
            points.push_back({v, glm::mix(cornerB[from], cornerB[to], s), from, s});
        }
        return points;
    }

    // ring() with the points of the leaves beside on its edges that lie on its scene triangle's
    // edges (SceneEdgePoints), in order along each edge.
    std::vector<RingPoint> withEdgePoints(int element) const {
        const std::vector<RingPoint> own = ring(element);
        const std::array<uint32_t, 3>& corners = mesh_.vertices(element);
        const std::array<Vec3, 3>& cornerB = mesh_.barycentrics(element);
        std::vector<RingPoint> all;
        for (size_t k = 0; k < 3; ++k) {
            std::vector<RingPoint> edge;
            std::ranges::copy_if(own, std::back_inserter(edge),
                                 [k](const RingPoint& p) { return p.edge == k; });
            const size_t next = (k + 1) % 3;
            for (int j = 0; j < 3; ++j) {
                if (std::abs(cornerB[k][j]) > kOnSceneEdge ||
                    std::abs(cornerB[next][j]) > kOnSceneEdge)
                    continue;
                for (const auto& [s, v] : edgePoints_.inside(mesh_, mesh_.sceneTriangle(element), j,
                                                             corners[k], corners[next])) {
                    const bool known = std::ranges::any_of(
                        edge, [s](const RingPoint& p) { return std::abs(p.s - s) <= kSamePoint; });
                    if (!known)
                        edge.push_back({v, glm::mix(cornerB[k], cornerB[next], s), k, s});
                }
            }
            std::ranges::sort(edge, {}, &RingPoint::s);
            all.insert(all.end(), edge.begin(), edge.end());
        }
        return all;
    }

    // The normal at barycentrics b of the leaf's scene triangle: the mesh's interpolated vertex
    // normals if it has them (Scene::surfaceAt's shading normal before normal mapping), else the
    // geometric normal.
    Vec3 normal(int element, const Vec3& b) const {
        if (source_.normals.empty())
            return mesh_.normal(element);
        const glm::uvec3& t = source_.triangles[mesh_.sceneTriangle(element)];
        const Vec3 n =
            b.x * source_.normals[t[0]] + b.y * source_.normals[t[1]] + b.z * source_.normals[t[2]];
        const float length = glm::length(n);
        return length > 0.0f ? n / length : mesh_.normal(element);
    }

    uint32_t newVertex(const Vec3& position, const Color& L, int element, const Vec3& b) {
        data_.positions.push_back(position);
        data_.normals.push_back(normal(element, b));
        radiance_.push_back(L);
        nextSame_.push_back(kNone);
        return uint32_t(data_.positions.size() - 1);
    }

    // The output vertex of mesh vertex v with radiance L and this leaf's normal: an existing one
    // when both agree (the usual case inside one material and one smooth or flat surface, away
    // from a cut), else a new one at the end of v's chain.
    uint32_t vertex(uint32_t v, const Color& L, int element, const Vec3& b) {
        const Vec3 n = normal(element, b);
        const auto [it, added] = firstOutput_.try_emplace(v, kNone);
        if (added) {
            const uint32_t out = newVertex(mesh_.position(v), L, element, b);
            firstOutput_[v] = out;
            return out;
        }
        uint32_t last = it->second;
        for (uint32_t out = last; out != kNone; out = nextSame_[out]) {
            if (sameRadiance(radiance_[out], L) && data_.normals[out] == n)
                return out;
            last = out;
        }
        // Linked by index once added: newVertex() grows nextSame_, which may move it.
        const uint32_t out = newVertex(mesh_.position(v), L, element, b);
        nextSame_[last] = out;
        return out;
    }

    const RadiosityMesh& mesh_;
    const Mesh& source_;
    const LeafCornerRadiance& cornerRadiance_;
    SceneEdgePoints edgePoints_;
    GltfMeshData data_;
    std::vector<Color> radiance_;                         // per output vertex, cd/m²
    std::unordered_map<uint32_t, uint32_t> firstOutput_;  // mesh vertex -> its first output vertex
    std::vector<uint32_t> nextSame_;  // output vertex -> the next one of the same mesh vertex
};

}  // namespace

BakeResult bakeRadiosity(const Scene& scene, const RadiosityMesh& mesh,
                         const LeafCornerRadiance& cornerRadiance, std::optional<float> exposure,
                         Progress* progress) {
    std::vector<std::vector<int>> leaves(scene.meshes().size());
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        if (mesh.isLeaf(int(e)))
            leaves[mesh.sceneMesh(int(e))].push_back(int(e));
    }

    BakeResult result;
    std::vector<MeshBaker> bakers;
    std::vector<WeightedRadiance> lit, emissive;
    for (size_t m = 0; m < leaves.size(); ++m) {
        if (leaves[m].empty())
            continue;
        bakers.emplace_back(scene, mesh, uint32_t(m), cornerRadiance);
        for (const int leaf : leaves[m])
            bakers.back().registerEdgePoints(leaf);
        for (const int leaf : leaves[m]) {
            bakers.back().addLeaf(leaf, lit, emissive);
            if (progress)
                progress->advance(1);
        }
        result.leaves += leaves[m].size();
    }

    if (exposure) {
        result.exposure = *exposure;
    } else {
        result.automaticExposure = true;
        result.exposureRadiance = weightedQuantile(
            lit.empty() ? std::move(emissive) : std::move(lit), kAutoExposureQuantile);
        result.exposure =
            result.exposureRadiance > 0.0f ? -std::log2(result.exposureRadiance) : 0.0f;
    }
    const float scale = std::exp2(result.exposure);

    result.model.origin = scene.description().origin;
    result.model.generator = std::string("penumbra ") + kVersion;
    for (MeshBaker& baker : bakers) {
        result.model.meshes.push_back(baker.finish(scale));
        result.vertices += result.model.meshes.back().positions.size();
        result.triangles += result.model.meshes.back().indices.size() / 3;
    }
    return result;
}

}  // namespace penumbra
