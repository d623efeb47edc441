// The triangle is laid in its own plane (x along its first edge, y across it, its normal out of
// the page, so that counter-clockwise in the plane is counter-clockwise seen from the front).
// Its edges and the segments are snap rounded (CGAL's Snap_rounding_2, exact arithmetic:
// Hobby 1999, "Practical segment intersection with finite precision output"; the iterated form
// of Halperin and Packer 2002) to a grid a millionth of the triangle's least height, so that
// they meet only at shared vertices however nearly they coincide or cross; then triangulated by
// CGAL's constrained Delaunay triangulation with them as constraints, and refined by CGAL's
// Delaunay mesher with a shape criterion only: no size bound, since the radiosity mesh
// subdivides each piece itself. The snapped outline's points are put back on the triangle's
// exact edges, and the input's end points where they were.
#include "radiosity/triangle_pieces.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Gmpq.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Snap_rounding_2.h>
#include <CGAL/Snap_rounding_traits_2.h>

#include <algorithm>
#include <list>
#include <map>
#include <optional>

namespace penumbra {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Delaunay_mesh_vertex_base_2<Kernel>;
using FaceBase = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using Structure = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Snap rounding leaves no crossings to compute; should rounding its grid's points to double
// make one, Exact_predicates_tag computes it in the kernel's inexact constructions, as CGAL
// documents for this kernel.
using Triangulation =
    CGAL::Constrained_Delaunay_triangulation_2<Kernel, Structure, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Triangulation>;
using Mesher = CGAL::Delaunay_mesher_2<Triangulation, Criteria>;
using Point = Kernel::Point_2;
using ExactKernel = CGAL::Simple_cartesian<CGAL::Gmpq>;
using SnapTraits = CGAL::Snap_rounding_traits_2<ExactKernel>;
using SnappedPolyline = std::list<ExactKernel::Point_2>;

// CGAL's default shape bound: sin^2 of the smallest angle it leaves, about 20.7 degrees.
constexpr double kShapeBound = 0.125;
// Refinement steps allowed per vertex of the input: Ruppert's algorithm terminates for input
// angles of 60 degrees or more; a segment meeting an edge at a tiny angle need not.
constexpr int kStepsPerInputVertex = 16;
// The least resolution, relative to the triangle's least height: a few float ulps of the
// barycentric coordinate across it. Also the snap rounding's pixel.
constexpr double kLeastResolution = 1e-6;
// The most resolution, relative to the triangle's least height: features are joined within the
// triangle, not across it (a thin triangle would otherwise have every point put on its edges).
constexpr double kMostResolutionPerHeight = 0.25;
// A barycentric coordinate under which a point counts as on the triangle's edge.
constexpr float kBorderBarycentric = 1e-6f;

// The triangle's plane: 2D coordinates of a barycentric point, and back.
class TrianglePlane {
  public:
    explicit TrianglePlane(const std::array<Vec3, 3>& corners) {
        // In double before subtracting: on a thin triangle the float difference of its corners
        // would tilt its plane by a part in 10^5.
        const glm::dvec3 e1 = glm::dvec3(corners[1]) - glm::dvec3(corners[0]);
        const glm::dvec3 e2 = glm::dvec3(corners[2]) - glm::dvec3(corners[0]);
        const glm::dvec3 u = glm::normalize(e1);
        const glm::dvec3 v = glm::cross(glm::normalize(glm::cross(e1, e2)), u);
        q1_ = {glm::dot(e1, u), 0.0};
        q2_ = {glm::dot(e2, u), glm::dot(e2, v)};
        det_ = q1_.x * q2_.y - q1_.y * q2_.x;
    }
    glm::dvec2 toPlane(const Vec3& b) const { return double(b.y) * q1_ + double(b.z) * q2_; }
    // The barycentric coordinates of a plane point on the triangle (a point on an edge may
    // come out a rounding error outside) or, with `edges` (bit k for the edge b_k = 0), on
    // one of its edges.
    Vec3 toBarycentric(const glm::dvec2& p, uint8_t edges = 0) const {
        const glm::dvec3 b = glm::max(unclamped(p), glm::dvec3(0.0));
        glm::dvec3 on = b;
        for (int k = 0; k < 3; ++k)
            if (edges & (1 << k))
                on[k] = 0.0;
        const double sum = on.x + on.y + on.z;
        return sum > 0.0 ? Vec3(on / sum) : Vec3(b / (b.x + b.y + b.z));
    }
    // The edges (bit k for b_k = 0) a plane point is within `distance` of.
    uint8_t edgesNear(const glm::dvec2& p, double distance) const {
        const glm::dvec3 b = unclamped(p);
        const std::array<double, 3> length = {glm::length(q2_ - q1_), glm::length(q2_),
                                              glm::length(q1_)};
        uint8_t edges = 0;
        for (int k = 0; k < 3; ++k)  // b_k times the height over edge k, |det| / length
            if (std::abs(b[k]) * std::abs(det_) / length[size_t(k)] <= distance)
                edges = uint8_t(edges | (1 << k));
        return edges;
    }
    double size() const {
        return std::max({glm::length(q1_), glm::length(q2_), glm::length(q2_ - q1_)});
    }
    double leastHeight() const { return std::abs(det_) / size(); }

  private:
    glm::dvec3 unclamped(const glm::dvec2& p) const {
        const double b1 = (p.x * q2_.y - p.y * q2_.x) / det_;
        const double b2 = (q1_.x * p.y - q1_.y * p.x) / det_;
        return {1.0 - b1 - b2, b1, b2};
    }

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
    // the edge, and then stays there: moved on to a second edge near a corner, it would take the
    // first edge's outline off the triangle, and the sliver between would be lost.
    void joinPointsToLines() {
        std::vector<bool> onEdge(points_.size(), false);
        for (Line& line : lines_) {
            for (int i = 3; i < int(points_.size()); ++i) {
                if (i == line.a || i == line.b || (line.edge && onEdge[size_t(i)]))
                    continue;
                const glm::dvec2 a = points_[size_t(line.a)], d = points_[size_t(line.b)] - a;
                const double t = glm::dot(points_[size_t(i)] - a, d) / glm::dot(d, d);
                const glm::dvec2 foot = a + t * d;
                if (t <= 0.0 || t >= 1.0 || glm::distance(foot, points_[size_t(i)]) > resolution_)
                    continue;
                if (line.edge) {
                    points_[size_t(i)] = foot;
                    onEdge[size_t(i)] = true;
                }
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

// The chains snap rounded: per piece of a chain (which chain in chainOf, its ends in ends), a
// polyline of the grid's points (in double), in order. No two of them cross; they meet at shared
// points or run along each other.
std::vector<std::vector<glm::dvec2>> snapRounded(const std::vector<glm::dvec2>& points,
                                                 const std::vector<std::vector<int>>& chains,
                                                 double pixel, std::vector<int>& chainOf,
                                                 std::vector<std::array<glm::dvec2, 2>>& ends) {
    std::list<ExactKernel::Segment_2> segments;
    chainOf.clear();
    ends.clear();
    for (size_t c = 0; c < chains.size(); ++c) {
        for (size_t i = 1; i < chains[c].size(); ++i) {
            const glm::dvec2 a = points[size_t(chains[c][i - 1])];
            const glm::dvec2 b = points[size_t(chains[c][i])];
            if (a == b)
                continue;
            segments.emplace_back(ExactKernel::Point_2(a.x, a.y), ExactKernel::Point_2(b.x, b.y));
            chainOf.push_back(int(c));
            ends.push_back({a, b});
        }
    }
    std::list<SnappedPolyline> snapped;
    // Iterated snap rounding (do_isr): no vertex ends closer than half a pixel to an edge it is
    // not on; the grid's points in the input's coordinates (int_output false).
    CGAL::snap_rounding_2<SnapTraits>(segments.begin(), segments.end(), snapped,
                                      ExactKernel::FT(pixel), true, false);
    std::vector<std::vector<glm::dvec2>> result;
    for (const SnappedPolyline& polyline : snapped) {
        std::vector<glm::dvec2>& out = result.emplace_back();
        for (const ExactKernel::Point_2& p : polyline)
            out.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y())});
    }
    return result;
}

// What the triangulation's points stand for: which of the triangle's edges (chains 0, 1, 2:
// b_k = 0) each lies on, a corner both of its edges; and where an end point of the input was
// before it was snapped, so that the pieces keep it where the caller put it (the triangle beside,
// cut by the same line on another grid, has its end there too).
struct SnappedPoints {
    std::map<Triangulation::Vertex_handle, uint8_t> edgesAt;
    std::map<Triangulation::Vertex_handle, glm::dvec2> unsnapped;
};

// Inserts the chains snap rounded as constraints.
void insertSnapped(Triangulation& cdt, SnappedPoints& snapped,
                   const std::vector<glm::dvec2>& points,
                   const std::vector<std::vector<int>>& chains, double pixel) {
    std::vector<int> chainOf;
    std::vector<std::array<glm::dvec2, 2>> ends;
    const std::vector<std::vector<glm::dvec2>> polylines =
        snapRounded(points, chains, pixel, chainOf, ends);
    for (size_t s = 0; s < polylines.size(); ++s) {
        Triangulation::Vertex_handle first, previous;
        for (const glm::dvec2& p : polylines[s]) {
            const Triangulation::Vertex_handle v = cdt.insert(Point(p.x, p.y));
            uint8_t& edges = snapped.edgesAt[v];
            if (chainOf[s] < 3)
                edges = uint8_t(edges | (1 << chainOf[s]));
            if (previous == Triangulation::Vertex_handle())
                first = v;
            else if (previous != v)
                cdt.insert_constraint(previous, v);
            previous = v;
        }
        // A polyline runs from its segment's source's pixel to its target's.
        snapped.unsnapped[first] = ends[s][0];
        snapped.unsnapped[previous] = ends[s][1];
    }
}

// The mesher splits constrained edges at new points: one on the outline (a constrained edge
// with the domain on one side only) lies on the edges within two of the grid's pixels of it.
void markNewPointsOnTheOutline(const Triangulation& cdt,
                               std::map<Triangulation::Vertex_handle, uint8_t>& edgesAt,
                               const TrianglePlane& plane, double pixel) {
    const auto inside = [&](Triangulation::Face_handle f) {
        return !cdt.is_infinite(f) && f->is_in_domain();
    };
    for (const Triangulation::Vertex_handle v : cdt.finite_vertex_handles()) {
        if (edgesAt.count(v))
            continue;
        bool outline = false;
        Triangulation::Edge_circulator e = cdt.incident_edges(v), done = e;
        do {
            const Triangulation::Face_handle f = e->first;
            outline =
                outline || (cdt.is_constrained(*e) && inside(f) != inside(f->neighbor(e->second)));
        } while (++e != done);
        edgesAt[v] = outline ? plane.edgesNear({v->point().x(), v->point().y()}, 2.0 * pixel) : 0;
    }
}

// Where the points of the triangle's edges go back to: the corners to the triangle's corners,
// the input's end points to where they were, and the points between (the mesher's splits of the
// outline) to the same fraction of the way between those beside them along the edge, so that a
// midpoint stays the midpoint the triangle beside has too.
std::map<Triangulation::Vertex_handle, glm::dvec2> placesOnTheEdges(const SnappedPoints& snapped,
                                                                    const TrianglePlane& plane) {
    std::map<Triangulation::Vertex_handle, glm::dvec2> places;
    std::array<glm::dvec2, 3> corner;
    for (int c = 0; c < 3; ++c)
        corner[size_t(c)] = plane.toPlane(Vec3(c == 0, c == 1, c == 2));
    for (int k = 0; k < 3; ++k) {
        const glm::dvec2 from = corner[size_t(k + 1) % 3], to = corner[size_t(k + 2) % 3];
        const auto along = [&](const glm::dvec2& p) { return glm::dot(p - from, to - from); };
        // (parameter of the snapped point, its place if known, the point), the corners first
        // and last.
        struct EdgePoint {
            double t;
            std::optional<glm::dvec2> place;
            Triangulation::Vertex_handle v;
        };
        std::vector<EdgePoint> points = {{along(from), from, {}}};
        for (const auto& [v, edges] : snapped.edgesAt) {
            if (edges != (1 << k))
                continue;
            const auto end = snapped.unsnapped.find(v);
            std::optional<glm::dvec2> place;
            if (end != snapped.unsnapped.end())
                place = end->second;
            points.push_back({along({v->point().x(), v->point().y()}), place, v});
        }
        points.push_back({along(to), to, {}});
        std::sort(points.begin() + 1, points.end() - 1,
                  [](const EdgePoint& a, const EdgePoint& b) { return a.t < b.t; });
        size_t previous = 0;
        for (size_t i = 1; i < points.size(); ++i) {
            if (!points[i].place)
                continue;
            for (size_t j = previous + 1; j < i; ++j) {
                const double span = points[i].t - points[previous].t;
                const double f =
                    span > 0.0 ? std::clamp((points[j].t - points[previous].t) / span, 0.0, 1.0)
                               : 0.5;
                places[points[j].v] = glm::mix(*points[previous].place, *points[i].place, f);
            }
            previous = i;
        }
    }
    return places;
}

// The pieces: the triangulation's faces inside the outline, their points in barycentrics, the
// outline's put back on the triangle's edges and its corners on the triangle's corners.
void collectPieces(const Triangulation& cdt, const SnappedPoints& snapped,
                   const TrianglePlane& plane, TrianglePieces& result) {
    // A corner is a point on two edges: the corner they share, b = 1 opposite both.
    const std::map<Triangulation::Vertex_handle, glm::dvec2> onEdges =
        placesOnTheEdges(snapped, plane);
    std::map<Triangulation::Vertex_handle, uint32_t> index;
    for (const Triangulation::Vertex_handle v : cdt.finite_vertex_handles()) {
        const uint8_t edges = snapped.edgesAt.at(v);
        if (edges == 0x3 || edges == 0x5 || edges == 0x6) {
            index[v] = edges == 0x6 ? 0u : edges == 0x5 ? 1u : 2u;
            continue;
        }
        const auto onEdge = onEdges.find(v);
        const auto end = snapped.unsnapped.find(v);
        const glm::dvec2 at = onEdge != onEdges.end() ? onEdge->second
                              : end != snapped.unsnapped.end()
                                  ? end->second
                                  : glm::dvec2(v->point().x(), v->point().y());
        index[v] = uint32_t(result.points.size());
        result.points.push_back(plane.toBarycentric(at, edges));
    }
    for (const Triangulation::Face_handle f : cdt.finite_face_handles()) {
        if (!f->is_in_domain())
            continue;
        const std::array<uint32_t, 3> piece = {index.at(f->vertex(0)), index.at(f->vertex(1)),
                                               index.at(f->vertex(2))};
        // A piece that the return to the exact edges and end points turned over or flattened
        // (a few of the grid's pixels wide) is left out: the pieces beside cover its place.
        const Vec3 &a = result.points[piece[0]], &b = result.points[piece[1]],
                   &c = result.points[piece[2]];
        const double twiceArea =
            (double(b.y) - a.y) * (double(c.z) - a.z) - (double(b.z) - a.z) * (double(c.y) - a.y);
        if (!(twiceArea > 0.0))
            continue;
        // CGAL's edge i is the one opposite vertex i: the edge from corner k to k + 1 is
        // opposite corner k + 2. The triangle's own edges are constrained too (the domain's
        // border): an edge whose ends share a zero barycentric lies on one.
        uint8_t cut = 0;
        for (int k = 0; k < 3; ++k) {
            const Vec3& from = result.points[piece[size_t(k)]];
            const Vec3& to = result.points[piece[size_t(k + 1) % 3]];
            const Vec3 low = glm::max(from, to);
            const bool border = std::min({low.x, low.y, low.z}) < kBorderBarycentric;
            if (f->is_constrained((k + 2) % 3) && !border)
                cut = uint8_t(cut | (1 << k));
        }
        result.pieces.push_back(piece);
        result.cutEdges.push_back(cut);
    }
}

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
    const double least = kLeastResolution * plane.leastHeight();
    const double most = std::max(least, kMostResolutionPerHeight * plane.leastHeight());
    PlanarInput input(plane, std::clamp(double(resolution), least, most));
    for (const TriangleSegment& segment : segments)
        input.addSegment(plane.toPlane(segment[0]), plane.toPlane(segment[1]));
    input.joinPointsToLines();

    const std::vector<std::vector<int>> chains = input.chains();
    Triangulation cdt;
    SnappedPoints snapped;
    insertSnapped(cdt, snapped, input.points(), chains, least);

    Mesher mesher(cdt, Criteria(kShapeBound, 0.0));
    mesher.init();  // the domain: every face inside the outline
    const int maxSteps = kStepsPerInputVertex * int(cdt.number_of_vertices());
    for (int step = 0; step < maxSteps && mesher.step_by_step_refine_mesh(); ++step) {
    }
    markNewPointsOnTheOutline(cdt, snapped.edgesAt, plane, least);
    collectPieces(cdt, snapped, plane, result);
    return result;
}

}  // namespace penumbra
