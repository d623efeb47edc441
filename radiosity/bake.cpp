#include "radiosity/bake.h"

#include "core/progress.h"
#include "core/scene.h"
#include "core/version.h"
#include "radiosity/radiosity_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
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

// Builds the glTF mesh of one scene mesh, leaf by leaf, with the radiance (not yet exposed) of
// every output vertex.
class MeshBaker {
  public:
    MeshBaker(const Scene& scene, const RadiosityMesh& mesh, uint32_t sceneMesh)
        : mesh_(mesh), source_(scene.meshes()[sceneMesh]) {
        const Material& material = scene.materials()[size_t(source_.material)];
        data_.name = source_.name;
        data_.material =
            material.name.empty() ? "material " + std::to_string(source_.material) : material.name;
        data_.doubleSided = material.doubleSided;
    }

    void addLeaf(int element, std::vector<WeightedRadiance>& lit,
                 std::vector<WeightedRadiance>& emissive) {
        const std::vector<uint32_t> boundary = mesh_.leafBoundary(element);
        const std::array<uint32_t, 3>& corners = mesh_.vertices(element);
        const std::array<Vec3, 3>& cornerB = mesh_.barycentrics(element);
        const Color& Le = mesh_.Le(element);

        // The boundary's vertices with their barycentrics in the scene triangle: the corners'
        // are exact; a T-vertex lies on the edge from the last corner passed to the next one.
        std::vector<uint32_t> ring;
        ring.reserve(boundary.size());
        int corner = -1;
        for (const uint32_t v : boundary) {
            Vec3 b;
            if (corner < 2 && v == corners[size_t(corner + 1)]) {
                ++corner;
                b = cornerB[size_t(corner)];
            } else {
                const int next = (corner + 1) % 3;
                const Vec3& p0 = mesh_.position(corners[size_t(corner)]);
                const float t = glm::length(mesh_.position(v) - p0) /
                                glm::length(mesh_.position(corners[size_t(next)]) - p0);
                b = glm::mix(cornerB[size_t(corner)], cornerB[size_t(next)], t);
            }
            ring.push_back(vertex(v, mesh_.vertexValue(v) + Le, element, b));
        }

        const size_t firstTriangle = data_.indices.size();
        if (ring.size() == 3) {
            data_.indices.insert(data_.indices.end(), ring.begin(), ring.end());
        } else {
            // Fan from the centroid, whose value is the Gouraud interpolation there.
            const Color centroidValue =
                (mesh_.vertexValue(corners[0]) + mesh_.vertexValue(corners[1]) +
                 mesh_.vertexValue(corners[2])) /
                    3.0f +
                Le;
            const Vec3 centroidB = (cornerB[0] + cornerB[1] + cornerB[2]) / 3.0f;
            const uint32_t centre =
                newVertex(mesh_.centroid(element), centroidValue, element, centroidB);
            for (size_t i = 0; i < ring.size(); ++i)
                data_.indices.insert(data_.indices.end(),
                                     {centre, ring[i], ring[(i + 1) % ring.size()]});
        }

        // Samples for the automatic exposure.
        std::vector<WeightedRadiance>& samples = maxComponent(Le) > 0.0f ? emissive : lit;
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
    // when both agree (the usual case inside one material and one smooth or flat surface), else a
    // new one.
    uint32_t vertex(uint32_t v, const Color& L, int element, const Vec3& b) {
        const Vec3 n = normal(element, b);
        const auto [it, added] = firstOutput_.try_emplace(v, kNone);
        uint32_t* link = &it->second;
        for (uint32_t out = *link; out != kNone; out = *link) {
            if (radiance_[out] == L && data_.normals[out] == n)
                return out;
            link = &nextSame_[out];
        }
        *link = newVertex(mesh_.position(v), L, element, b);
        return *link;
    }

    const RadiosityMesh& mesh_;
    const Mesh& source_;
    GltfMeshData data_;
    std::vector<Color> radiance_;                         // per output vertex, cd/m²
    std::unordered_map<uint32_t, uint32_t> firstOutput_;  // mesh vertex -> its first output vertex
    std::vector<uint32_t> nextSame_;  // output vertex -> the next one of the same mesh vertex
};

}  // namespace

BakeResult bakeRadiosity(const Scene& scene, const RadiosityMesh& mesh,
                         std::optional<float> exposure, Progress* progress) {
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
        bakers.emplace_back(scene, mesh, uint32_t(m));
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
