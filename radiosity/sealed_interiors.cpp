#include "radiosity/sealed_interiors.h"

#include "core/scene.h"
#include "radiosity/form_factor.h"
#include "radiosity/quiet_openmesh_errors.h"
#include "radiosity/radiosity_mesh.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <array>
#include <cmath>
#include <map>

namespace penumbra {

namespace {

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

struct ClosedSurface {
    std::vector<uint32_t> triangles;  // of its scene mesh
    bool frontFacesInside = false;
    Bounds3 bounds;
};

// Where light starts inside the scene: point and spot lights, and a point (the centroid) of each
// emissive triangle. Directional lights and the sky come from outside everything.
std::vector<Vec3> lightPoints(const Scene& scene) {
    std::vector<Vec3> points;
    for (const PunctualLightDesc& light : scene.description().lights) {
        if (light.type != PunctualType::Directional)
            points.push_back(light.position);
    }
    for (const Mesh& mesh : scene.meshes()) {
        if (!scene.materials()[static_cast<size_t>(mesh.material)].isEmissive())
            continue;
        for (const glm::uvec3& t : mesh.triangles)
            points.push_back((mesh.positions[t.x] + mesh.positions[t.y] + mesh.positions[t.z]) /
                             3.0f);
    }
    return points;
}

// The closed surfaces among the triangles of one mesh (see sealed_interiors.h). OpenMesh builds
// the welded mesh and refuses any face that would make it non-manifold or inconsistently wound;
// a connected part touching a refused face, or with a boundary edge, is open.
std::vector<ClosedSurface> closedSurfaces(const Mesh& mesh) {
    TriMesh welded;
    std::map<std::array<float, 3>, TriMesh::VertexHandle> byPosition;
    std::vector<TriMesh::VertexHandle> vertex(mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        const Vec3& p = mesh.positions[i];
        const auto [it, inserted] = byPosition.try_emplace({p.x, p.y, p.z});
        if (inserted)
            it->second = welded.add_vertex(TriMesh::Point(p.x, p.y, p.z));
        vertex[i] = it->second;
    }
    std::vector<char> nearRefused(welded.n_vertices(), 0);
    std::vector<uint32_t> triangleOfFace;
    {
        const QuietOpenMeshErrors quiet;
        for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
            const std::array<TriMesh::VertexHandle, 3> v = {vertex[mesh.triangles[t].x],
                                                            vertex[mesh.triangles[t].y],
                                                            vertex[mesh.triangles[t].z]};
            const bool distinct = v[0] != v[1] && v[1] != v[2] && v[2] != v[0];
            if (!distinct || !welded.add_face(v[0], v[1], v[2]).is_valid()) {
                for (const auto& h : v)
                    nearRefused[static_cast<size_t>(h.idx())] = 1;
                continue;
            }
            triangleOfFace.push_back(t);
        }
    }
    std::vector<ClosedSurface> result;
    std::vector<char> visited(welded.n_faces(), 0);
    std::vector<TriMesh::FaceHandle> stack;
    for (const TriMesh::FaceHandle start : welded.faces()) {
        if (visited[static_cast<size_t>(start.idx())])
            continue;
        ClosedSurface surface;
        bool closed = true;
        double volume = 0.0, area = 0.0;
        const glm::dvec3 origin(mesh.positions[mesh.triangles[triangleOfFace[start.idx()]].x]);
        visited[static_cast<size_t>(start.idx())] = 1;
        stack.assign(1, start);
        while (!stack.empty()) {
            const TriMesh::FaceHandle f = stack.back();
            stack.pop_back();
            const uint32_t t = triangleOfFace[static_cast<size_t>(f.idx())];
            surface.triangles.push_back(t);
            std::array<glm::dvec3, 3> p;
            for (int c = 0; c < 3; ++c) {
                const Vec3& q = mesh.positions[mesh.triangles[t][c]];
                surface.bounds.extend(q);
                p[c] = glm::dvec3(q) - origin;
            }
            volume += glm::dot(p[0], glm::cross(p[1], p[2])) / 6.0;
            area += 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
            for (const auto h : welded.fh_range(f)) {
                if (welded.is_boundary(welded.opposite_halfedge_handle(h)) ||
                    nearRefused[static_cast<size_t>(welded.to_vertex_handle(h).idx())])
                    closed = false;
            }
            for (const TriMesh::FaceHandle g : welded.ff_range(f)) {
                if (!visited[static_cast<size_t>(g.idx())]) {
                    visited[static_cast<size_t>(g.idx())] = 1;
                    stack.push_back(g);
                }
            }
        }
        // A doubly covered flat sheet is closed but encloses nothing.
        if (closed && std::abs(volume) > 1e-6 * area * std::sqrt(area)) {
            surface.frontFacesInside = volume < 0.0;
            result.push_back(std::move(surface));
        }
    }
    return result;
}

bool enclosesAny(const Mesh& mesh, const ClosedSurface& surface, const std::vector<Vec3>& points) {
    for (const Vec3& point : points) {
        if (glm::any(glm::lessThan(point, surface.bounds.lo)) ||
            glm::any(glm::greaterThan(point, surface.bounds.hi)))
            continue;
        double solidAngle = 0.0;
        for (const uint32_t t : surface.triangles) {
            const glm::uvec3 i = mesh.triangles[t];
            solidAngle += triangleSolidAngle(
                point, {mesh.positions[i.x], mesh.positions[i.y], mesh.positions[i.z]});
        }
        if (std::abs(solidAngle) > 2.0 * kPi)  // winding number beyond 1/2
            return true;
    }
    return false;
}

}  // namespace

SealedInteriors::SealedInteriors(const Scene& scene) : side_(scene.meshes().size()) {
    const std::vector<Vec3> lights = lightPoints(scene);
    for (size_t m = 0; m < scene.meshes().size(); ++m) {
        const Mesh& mesh = scene.meshes()[m];
        const Material& material = scene.materials()[static_cast<size_t>(mesh.material)];
        if (!holdsMaterial(material) || material.alphaMode != AlphaMode::Opaque ||
            material.isEmissive())
            continue;
        for (const ClosedSurface& surface : closedSurfaces(mesh)) {
            if (enclosesAny(mesh, surface, lights))
                continue;
            if (side_[m].empty())
                side_[m].assign(mesh.triangles.size(), kNone);
            for (const uint32_t t : surface.triangles)
                side_[m][t] = surface.frontFacesInside ? kFront : kBack;
            ++count_;
        }
    }
}

}  // namespace penumbra
