#include "radiosity/held_triangles.h"

#include "core/scene.h"
#include "radiosity/radiosity_mesh.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

std::vector<HeldTriangle> heldTriangles(const Scene& scene) {
    std::vector<HeldTriangle> held;
    const std::span<const Mesh> meshes = scene.meshes();
    for (uint32_t m = 0; m < meshes.size(); ++m) {
        const Material& material = scene.materials()[meshes[m].material];
        if (!holdsMaterial(material))
            continue;
        for (uint32_t t = 0; t < meshes[m].triangles.size(); ++t) {
            HeldTriangle h;
            h.mesh = m;
            h.triangle = t;
            for (int c = 0; c < 3; ++c)
                h.p[size_t(c)] = glm::dvec3(meshes[m].positions[meshes[m].triangles[t][c]]);
            const glm::dvec3 cross = glm::cross(h.p[1] - h.p[0], h.p[2] - h.p[0]);
            h.area = 0.5 * glm::length(cross);
            if (!(h.area > 0.0) || !std::isfinite(h.area))
                continue;
            h.normal = cross / (2.0 * h.area);
            h.twoSided = material.doubleSided;
            h.lo = glm::min(h.p[0], glm::min(h.p[1], h.p[2]));
            h.hi = glm::max(h.p[0], glm::max(h.p[1], h.p[2]));
            held.push_back(h);
        }
    }
    return held;
}

glm::dvec3 barycentric(const HeldTriangle& t, const glm::dvec3& x) {
    const glm::dvec3 e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0], d = x - t.p[0];
    const double twice = 2.0 * t.area;
    const double b1 = glm::dot(glm::cross(d, e2), t.normal) / twice;
    const double b2 = glm::dot(glm::cross(e1, d), t.normal) / twice;
    return {1.0 - b1 - b2, b1, b2};
}

bool planeCrossing(const std::array<glm::dvec3, 3>& p, const glm::dvec3& normal,
                   const glm::dvec3& origin, double tolerance, glm::dvec3& from, glm::dvec3& to) {
    std::array<double, 3> d;
    for (size_t i = 0; i < 3; ++i)
        d[i] = glm::dot(normal, p[i] - origin);
    std::vector<glm::dvec3> points;
    for (size_t i = 0; i < 3; ++i) {
        const size_t j = (i + 1) % 3;
        if (std::abs(d[i]) <= tolerance)
            points.push_back(p[i] - d[i] * normal);
        if ((d[i] > tolerance && d[j] < -tolerance) || (d[i] < -tolerance && d[j] > tolerance))
            points.push_back(p[i] + d[i] / (d[i] - d[j]) * (p[j] - p[i]));
    }
    if (points.size() < 2)
        return false;
    from = points[0];
    to = points[1];
    for (size_t i = 0; i < points.size(); ++i) {
        for (size_t j = i + 1; j < points.size(); ++j) {
            if (glm::distance(points[i], points[j]) > glm::distance(from, to)) {
                from = points[i];
                to = points[j];
            }
        }
    }
    return true;
}

bool clipToTriangle(const HeldTriangle& t, const glm::dvec3& from, const glm::dvec3& to,
                    double tolerance, double minLength, TriangleSegment& segment) {
    // Each barycentric coordinate, linear along the segment, kept >= 0. An end within the
    // tolerance of an edge (as a distance: b_k times the height over edge k) is moved onto it.
    const glm::dvec3 ba = barycentric(t, from), bb = barycentric(t, to);
    std::array<double, 3> height;
    for (int k = 0; k < 3; ++k) {
        const glm::dvec3 edge = t.p[size_t(k + 2) % 3] - t.p[size_t(k + 1) % 3];
        height[size_t(k)] = 2.0 * t.area / glm::length(edge);
    }
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < 3; ++k) {
        const double slope = bb[k] - ba[k];
        const double slack = tolerance / height[size_t(k)];
        if (std::abs(slope) <= 1e-12) {
            if (ba[k] < -slack)
                return false;
            continue;
        }
        const double onEdge = -ba[k] / slope;  // where b_k = 0
        const double reach = slack / std::abs(slope);
        if (slope > 0.0)
            t0 = std::abs(t0 - onEdge) <= reach ? onEdge : std::max(t0, onEdge);
        else
            t1 = std::abs(t1 - onEdge) <= reach ? onEdge : std::min(t1, onEdge);
    }
    if (!(t1 > t0) || (t1 - t0) * glm::distance(from, to) < minLength)
        return false;
    std::array<glm::dvec3, 2> ends = {ba + t0 * (bb - ba), ba + t1 * (bb - ba)};
    // On an edge of the triangle: its neighbour's, already an edge of the mesh.
    for (int k = 0; k < 3; ++k) {
        if (std::abs(ends[0][k]) * height[size_t(k)] <= tolerance &&
            std::abs(ends[1][k]) * height[size_t(k)] <= tolerance)
            return false;
    }
    for (size_t e = 0; e < 2; ++e) {
        glm::dvec3& b = ends[e];
        for (int k = 0; k < 3; ++k) {
            if (b[k] * height[size_t(k)] <= tolerance)
                b[k] = 0.0;
        }
        b /= b.x + b.y + b.z;
        segment[e] = Vec3(b);
    }
    return true;
}

void keepLongest(const HeldTriangle& t, std::vector<TriangleSegment>& segments, size_t count) {
    if (segments.size() <= count)
        return;
    const auto length = [&](const TriangleSegment& s) {
        return glm::length(t.p[0] * double(s[0].x - s[1].x) + t.p[1] * double(s[0].y - s[1].y) +
                           t.p[2] * double(s[0].z - s[1].z));
    };
    std::nth_element(segments.begin(), segments.begin() + ptrdiff_t(count), segments.end(),
                     [&](const auto& a, const auto& b) { return length(a) > length(b); });
    segments.resize(count);
}

std::span<const TriangleSegment> SegmentsByTriangle::on(uint32_t mesh, uint32_t triangle) const {
    const auto it = segments_.find(triangleKey(mesh, triangle));
    if (it == segments_.end())
        return {};
    return it->second;
}

void SegmentsByTriangle::set(const HeldTriangle& t, std::vector<TriangleSegment> segments) {
    if (!segments.empty())
        segments_[triangleKey(t.mesh, t.triangle)] = std::move(segments);
}

std::vector<GridBox> boxesOf(const std::vector<HeldTriangle>& triangles) {
    std::vector<GridBox> boxes;
    boxes.reserve(triangles.size());
    for (const HeldTriangle& t : triangles)
        boxes.push_back({t.lo, t.hi});
    return boxes;
}

}  // namespace penumbra
