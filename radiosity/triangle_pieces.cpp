// The triangle is laid in its own plane (x along its first edge, y across it, its normal out of
// the page, so that counter-clockwise in the plane is counter-clockwise seen from the front),
// triangulated by CGAL's constrained Delaunay triangulation with its edges and the segments as
// constraints, and refined by CGAL's Delaunay mesher with a shape criterion only: no size bound,
// since the radiosity mesh subdivides each piece itself.
#include "radiosity/triangle_pieces.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <map>

namespace penumbra {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Delaunay_mesh_vertex_base_2<Kernel>;
using FaceBase = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using Structure = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Segments may cross: Exact_predicates_tag computes their crossings in the kernel's inexact
// constructions, as CGAL documents for this kernel (Exact_intersections_tag is for kernels with
// exact constructions; with this one the mesher crashed on nearly coincident segments).
using Triangulation =
    CGAL::Constrained_Delaunay_triangulation_2<Kernel, Structure, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Triangulation>;
using Mesher = CGAL::Delaunay_mesher_2<Triangulation, Criteria>;
using Point = Kernel::Point_2;

// CGAL's default shape bound: sin^2 of the smallest angle it leaves, about 20.7 degrees.
constexpr double kShapeBound = 0.125;
// Refinement steps allowed per vertex of the input: Ruppert's algorithm terminates for input
// angles of 60 degrees or more; a segment meeting an edge at a tiny angle need not.
constexpr int kStepsPerInputVertex = 16;
// The least resolution, relative to the triangle's longest edge: a few float ulps of barycentrics.
constexpr double kLeastResolution = 1e-6;
// A barycentric coordinate under which a point counts as on the triangle's edge.
constexpr float kBorderBarycentric = 1e-6f;

// The triangle's plane: 2D coordinates of a barycentric point, and back.
class TrianglePlane {
  public:
    explicit TrianglePlane(const std::array<Vec3, 3>& corners) {
        const glm::dvec3 e1 = glm::dvec3(corners[1] - corners[0]);
        const glm::dvec3 e2 = glm::dvec3(corners[2] - corners[0]);
        const glm::dvec3 u = glm::normalize(e1);
        const glm::dvec3 v = glm::cross(glm::normalize(glm::cross(e1, e2)), u);
        q1_ = {glm::dot(e1, u), 0.0};
        q2_ = {glm::dot(e2, u), glm::dot(e2, v)};
        det_ = q1_.x * q2_.y - q1_.y * q2_.x;
    }
    glm::dvec2 toPlane(const Vec3& b) const { return double(b.y) * q1_ + double(b.z) * q2_; }
    Vec3 toBarycentric(const glm::dvec2& p) const {
        const double b1 = (p.x * q2_.y - p.y * q2_.x) / det_;
        const double b2 = (q1_.x * p.y - q1_.y * p.x) / det_;
        // A point on an edge may come out a rounding error outside.
        const glm::dvec3 b = glm::max(glm::dvec3(1.0 - b1 - b2, b1, b2), glm::dvec3(0.0));
        return Vec3(b / (b.x + b.y + b.z));
    }
    double size() const {
        return std::max({glm::length(q1_), glm::length(q2_), glm::length(q2_ - q1_)});
    }

  private:
    glm::dvec2 q1_{0.0}, q2_{0.0};  // corner 0 is the origin
    double det_ = 1.0;
};

// The input in the plane, with the features finer than the resolution joined: end points
// closer than it merged, an end point closer than it to a segment (or to an edge) put on it, so
// that the triangulation never has to resolve a gap of a rounding error (an end point a tenth of
// a micrometre beside another segment made 99 of 224 pieces flat in float).
class PlanarInput {
  public:
    PlanarInput(const TrianglePlane& plane, double resolution) : resolution_(resolution) {
        for (int c = 0; c < 3; ++c)
            points_.push_back(plane.toPlane(Vec3(c == 0, c == 1, c == 2)));
        for (int k = 0; k < 3; ++k)  // edge k, opposite corner k, b_k = 0
            lines_.push_back({(k + 1) % 3, (k + 2) % 3, true, {}});
    }
    void addSegment(const glm::dvec2& a, const glm::dvec2& b) {
        const int i = addPoint(a), j = addPoint(b);
        if (i != j)
            lines_.push_back({i, j, false, {}});
    }
    // Puts every end point within the resolution of a line's inside on it; an edge's moves onto
    // the edge.
    void joinPointsToLines() {
        for (Line& line : lines_) {
            for (int i = 3; i < int(points_.size()); ++i) {
                if (i == line.a || i == line.b)
                    continue;
                const glm::dvec2 a = points_[size_t(line.a)], d = points_[size_t(line.b)] - a;
                const double t = glm::dot(points_[size_t(i)] - a, d) / glm::dot(d, d);
                const glm::dvec2 foot = a + t * d;
                if (t <= 0.0 || t >= 1.0 || glm::distance(foot, points_[size_t(i)]) > resolution_)
                    continue;
                if (line.edge)
                    points_[size_t(i)] = foot;
                line.inside.push_back({t, i});
            }
        }
    }
    const std::vector<glm::dvec2>& points() const { return points_; }
    // Each line as a chain of point indices from one end to the other through the points on it.
    std::vector<std::vector<int>> chains() const {
        std::vector<std::vector<int>> result;
        for (Line line : lines_) {
            std::sort(line.inside.begin(), line.inside.end());
            std::vector<int> chain = {line.a};
            for (const auto& [t, i] : line.inside)
                chain.push_back(i);
            chain.push_back(line.b);
            result.push_back(std::move(chain));
        }
        return result;
    }

  private:
    struct Line {
        int a = 0, b = 0;
        bool edge = false;
        std::vector<std::pair<double, int>> inside;  // (parameter from a to b, point)
    };
    int addPoint(const glm::dvec2& p) {
        for (size_t i = 0; i < points_.size(); ++i)
            if (glm::distance(points_[i], p) <= resolution_)
                return int(i);
        points_.push_back(p);
        return int(points_.size()) - 1;
    }

    double resolution_;
    std::vector<glm::dvec2> points_;
    std::vector<Line> lines_;
};

}  // namespace

TrianglePieces cutTriangle(const std::array<Vec3, 3>& corners,
                           std::span<const TriangleSegment> segments, float resolution) {
    TrianglePieces result;
    result.points = {Vec3(1.0f, 0.0f, 0.0f), Vec3(0.0f, 1.0f, 0.0f), Vec3(0.0f, 0.0f, 1.0f)};
    if (segments.empty()) {
        result.pieces = {{0, 1, 2}};
        result.cutEdges = {0};
        return result;
    }
    const TrianglePlane plane(corners);
    PlanarInput input(plane, std::max(double(resolution), kLeastResolution * plane.size()));
    for (const TriangleSegment& segment : segments)
        input.addSegment(plane.toPlane(segment[0]), plane.toPlane(segment[1]));
    input.joinPointsToLines();

    Triangulation cdt;
    std::vector<Triangulation::Vertex_handle> vertex;
    for (const glm::dvec2& p : input.points())
        vertex.push_back(cdt.insert(Point(p.x, p.y)));
    for (const std::vector<int>& chain : input.chains()) {
        for (size_t i = 1; i < chain.size(); ++i) {
            const auto a = vertex[size_t(chain[i - 1])], b = vertex[size_t(chain[i])];
            if (a != b)
                cdt.insert_constraint(a, b);
        }
    }

    Mesher mesher(cdt, Criteria(kShapeBound, 0.0));
    mesher.init();  // the domain: every bounded face, i.e. the whole triangle
    const int maxSteps = kStepsPerInputVertex * int(cdt.number_of_vertices());
    for (int step = 0; step < maxSteps && mesher.step_by_step_refine_mesh(); ++step) {
    }

    std::map<Triangulation::Vertex_handle, uint32_t> index;
    for (int c = 0; c < 3; ++c)
        index[vertex[size_t(c)]] = uint32_t(c);
    for (const Triangulation::Vertex_handle v : cdt.finite_vertex_handles()) {
        if (index.count(v))
            continue;
        index[v] = uint32_t(result.points.size());
        result.points.push_back(plane.toBarycentric({v->point().x(), v->point().y()}));
    }
    for (const Triangulation::Face_handle f : cdt.finite_face_handles()) {
        if (!f->is_in_domain())
            continue;
        const std::array<uint32_t, 3> piece = {index.at(f->vertex(0)), index.at(f->vertex(1)),
                                               index.at(f->vertex(2))};
        // CGAL's edge i is the one opposite vertex i: the edge from corner k to k + 1 is
        // opposite corner k + 2. The triangle's own edges are constrained too (the domain's
        // border): an edge whose ends share a zero barycentric (to rounding) lies on one.
        uint8_t cut = 0;
        for (int k = 0; k < 3; ++k) {
            const Vec3& a = result.points[piece[size_t(k)]];
            const Vec3& b = result.points[piece[size_t(k + 1) % 3]];
            const Vec3 low = glm::max(a, b);
            const bool border = std::min({low.x, low.y, low.z}) < kBorderBarycentric;
            if (f->is_constrained((k + 2) % 3) && !border)
                cut = uint8_t(cut | (1 << k));
        }
        result.pieces.push_back(piece);
        result.cutEdges.push_back(cut);
    }
    return result;
}

}  // namespace penumbra
