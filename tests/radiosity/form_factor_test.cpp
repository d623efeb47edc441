// Form factors against the closed forms of Howell's catalogue ("A Catalog of Radiation Heat
// Transfer Configuration Factors", 3rd ed.), reciprocity and a closed enclosure.
#include "radiosity/form_factor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace penumbra {
namespace {

using std::numbers::pi;

// Every catalogue configuration must be matched within 0.5 %.
constexpr double kCatalogueTolerance = 0.005;

// Quad o, o + u, o + u + v, o + v; its front faces along u x v.
std::vector<Vec3> rectangle(const Vec3& o, const Vec3& u, const Vec3& v) {
    return {o, o + u, o + u + v, o + v};
}

std::vector<Vec3> reversed(std::vector<Vec3> polygon) {
    return {polygon.rbegin(), polygon.rend()};
}

double polygonArea(const std::vector<Vec3>& polygon) {
    glm::dvec3 sum(0.0);
    for (size_t i = 0; i < polygon.size(); ++i)
        sum += glm::cross(glm::dvec3(polygon[i]), glm::dvec3(polygon[(i + 1) % polygon.size()]));
    return 0.5 * glm::length(sum);
}

// Differential element to a parallel a x b rectangle at distance c, on the normal through one of
// its corners (Howell B-3), X = a / c, Y = b / c.
double parallelRectangleCorner(double a, double b, double c) {
    const double x = a / c, y = b / c;
    const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
    return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * pi);
}

// Differential element to a rectangle in a perpendicular plane at distance c, one edge (length a)
// in the element's plane, the element on the normal to the rectangle's plane through a corner;
// the other side is b (Howell's section B, e.g. as tabulated in BRE BR 187):
// F = 1/(2 pi) [atan(X) - 1/sqrt(1 + Y^2) atan(X / sqrt(1 + Y^2))], X = a / c, Y = b / c.
double perpendicularRectangleCorner(double a, double b, double c) {
    const double x = a / c, y = b / c, sy = std::sqrt(1 + y * y);
    return (std::atan(x) - std::atan(x / sy) / sy) / (2 * pi);
}

// Two equal parallel directly opposed a x b rectangles at distance c (Howell C-11).
double opposedRectangles(double a, double b, double c) {
    const double x = a / c, y = b / c, x2 = x * x, y2 = y * y;
    const double sx = std::sqrt(1 + x2), sy = std::sqrt(1 + y2);
    return 2 / (pi * x * y) *
           (0.5 * std::log((1 + x2) * (1 + y2) / (1 + x2 + y2)) + x * sy * std::atan(x / sy) +
            y * sx * std::atan(y / sx) - x * std::atan(x) - y * std::atan(y));
}

// From a w x l rectangle to an h x l rectangle sharing its edge of length l at 90 degrees
// (Howell C-14), W = w / l, H = h / l.
double perpendicularRectanglesCommonEdge(double w, double h, double l) {
    const double ww = (w / l) * (w / l), hh = (h / l) * (h / l), wW = w / l, hH = h / l;
    const double s = ww + hh;
    const double logTerm = std::log((1 + ww) * (1 + hh) / (1 + s)) +
                           ww * std::log(ww * (1 + s) / ((1 + ww) * s)) +
                           hh * std::log(hh * (1 + s) / ((1 + hh) * s));
    return (wW * std::atan(1 / wW) + hH * std::atan(1 / hH) -
            std::sqrt(s) * std::atan(1 / std::sqrt(s)) + 0.25 * logTerm) /
           (pi * wW);
}

// Disc of radius r1 to a coaxial parallel disc of radius r2 at distance h (Howell C-40).
double coaxialDiscs(double r1, double r2, double h) {
    const double R1 = r1 / h, R2 = r2 / h, x = 1 + (1 + R2 * R2) / (R1 * R1);
    return (x - std::sqrt(x * x - 4 * (R2 / R1) * (R2 / R1))) / 2;
}

// Regular n-gon with the area of the disc of radius r, centred on the z axis at height z, facing
// +z (or -z when facingDown).
std::vector<Vec3> discPolygon(double r, double z, int n, bool facingDown) {
    const double circumradius = r * std::sqrt(2 * pi / (n * std::sin(2 * pi / n)));
    std::vector<Vec3> polygon;
    for (int i = 0; i < n; ++i) {
        const double angle = (facingDown ? -1 : 1) * 2 * pi * i / n;
        polygon.emplace_back(circumradius * std::cos(angle), circumradius * std::sin(angle), z);
    }
    return polygon;
}

void expectRelative(double value, double expected, double tolerance) {
    EXPECT_NEAR(value, expected, tolerance * expected) << "relative error " << value / expected - 1;
}

TEST(PointToPolygon, ParallelRectangleOnTheNormalThroughACorner) {
    const Vec3 p(0.0f), n(0, 0, 1);
    for (float a : {0.1f, 1.0f, 4.0f})
        for (float b : {0.3f, 1.0f, 10.0f})
            for (float c : {0.2f, 1.0f, 5.0f}) {
                SCOPED_TRACE(testing::Message() << "a " << a << " b " << b << " c " << c);
                const auto polygon = rectangle({0, 0, c}, {a, 0, 0}, {0, b, 0});
                expectRelative(pointToPolygonFormFactor(p, n, polygon),
                               parallelRectangleCorner(a, b, c), 1e-5);
            }
}

TEST(PointToPolygon, ParallelRectangleCentredAndOffsetBySuperposition) {
    const Vec3 n(0, 0, 1);
    const float a = 2.0f, b = 3.0f, c = 0.7f;
    const auto polygon = rectangle({0, 0, c}, {a, 0, 0}, {0, b, 0});
    // Below the centre: four corner rectangles.
    expectRelative(pointToPolygonFormFactor({a / 2, b / 2, 0}, n, polygon),
                   4 * parallelRectangleCorner(a / 2, b / 2, c), 1e-5);
    // Below an inside point (0.5, 1): the four rectangles it splits the rectangle into.
    expectRelative(pointToPolygonFormFactor({0.5f, 1.0f, 0}, n, polygon),
                   parallelRectangleCorner(0.5, 1, c) + parallelRectangleCorner(1.5, 1, c) +
                       parallelRectangleCorner(0.5, 2, c) + parallelRectangleCorner(1.5, 2, c),
                   1e-5);
    // Below an outside point (-0.5, -1): the rectangle grown to it minus the two strips plus
    // their overlap.
    expectRelative(pointToPolygonFormFactor({-0.5f, -1.0f, 0}, n, polygon),
                   parallelRectangleCorner(a + 0.5, b + 1, c) -
                       parallelRectangleCorner(0.5, b + 1, c) -
                       parallelRectangleCorner(a + 0.5, 1, c) + parallelRectangleCorner(0.5, 1, c),
                   1e-5);
}

TEST(PointToPolygon, PerpendicularRectangle) {
    const Vec3 p(0.0f), n(0, 0, 1);
    for (float a : {0.2f, 1.0f, 5.0f})
        for (float b : {0.2f, 1.0f, 5.0f})
            for (float c : {0.5f, 2.0f}) {
                SCOPED_TRACE(testing::Message() << "a " << a << " b " << b << " c " << c);
                const auto polygon = rectangle({0, c, 0}, {a, 0, 0}, {0, 0, b});
                expectRelative(pointToPolygonFormFactor(p, n, polygon),
                               perpendicularRectangleCorner(a, b, c), 1e-5);
            }
}

TEST(PointToPolygon, OnlyThePartAboveTheTangentPlaneCounts) {
    const Vec3 p(0.0f), n(0, 0, 1);
    // The same perpendicular rectangle, extended below the tangent plane of p.
    const auto above = rectangle({0, 1, 0}, {2, 0, 0}, {0, 0, 1.5f});
    const auto straddling = rectangle({0, 1, -3}, {2, 0, 0}, {0, 0, 4.5f});
    EXPECT_NEAR(pointToPolygonFormFactor(p, n, straddling), pointToPolygonFormFactor(p, n, above),
                1e-7);
    // A triangle with one vertex below, against its clipped quad computed by hand.
    const std::vector<Vec3> triangle = {{-1, 1, 1}, {1, 1, 1}, {0, 1, -1}};
    const std::vector<Vec3> clipped = {{-1, 1, 1}, {1, 1, 1}, {0.5f, 1, 0}, {-0.5f, 1, 0}};
    EXPECT_NEAR(pointToPolygonFormFactor(p, n, triangle), pointToPolygonFormFactor(p, n, clipped),
                1e-7);
    // Entirely below: nothing.
    EXPECT_EQ(pointToPolygonFormFactor(p, n, rectangle({0, 0, -1}, {1, 0, 0}, {0, 1, 0})), 0.0);
}

TEST(PointToPolygon, WindingAndSideOfThePolygonDoNotMatter) {
    const Vec3 n(0, 0, 1);
    const auto polygon = rectangle({-0.3f, 0.2f, 1.0f}, {1.2f, 0.3f, 0.4f}, {-0.2f, 0.9f, 0.1f});
    const double front = pointToPolygonFormFactor({0, 0, 0}, n, polygon);
    EXPECT_GT(front, 0.0);
    EXPECT_NEAR(pointToPolygonFormFactor({0, 0, 0}, n, reversed(polygon)), front, 1e-12);
    // p mirrored through the polygon's plane, looking at it from the other side.
    const glm::dvec3 e1 = glm::dvec3(polygon[1] - polygon[0]),
                     e2 = glm::dvec3(polygon[3] - polygon[0]);
    const glm::dvec3 m = glm::normalize(glm::cross(e1, e2));
    const glm::dvec3 o(polygon[0]);
    const glm::dvec3 mirrored = -2.0 * glm::dot(-o, m) * m;
    const glm::dvec3 mirroredNormal = glm::dvec3(n) - 2.0 * glm::dot(glm::dvec3(n), m) * m;
    EXPECT_NEAR(pointToPolygonFormFactor(Vec3(mirrored), Vec3(mirroredNormal), polygon), front,
                1e-6);
}

TEST(PointToPolygon, DegeneratePolygonsGiveZero) {
    const Vec3 p(0.0f), n(0, 0, 1);
    EXPECT_EQ(pointToPolygonFormFactor(p, n, std::vector<Vec3>{}), 0.0);
    EXPECT_EQ(pointToPolygonFormFactor(p, n, std::vector<Vec3>{{0, 0, 1}, {1, 0, 1}}), 0.0);
    const std::vector<Vec3> collinear = {{0, 0, 1}, {1, 0, 1}, {3, 0, 1}};
    EXPECT_NEAR(pointToPolygonFormFactor(p, n, collinear), 0.0, 1e-12);
    const std::vector<Vec3> point = {{1, 2, 1}, {1, 2, 1}, {1, 2, 1}};
    EXPECT_EQ(pointToPolygonFormFactor(p, n, point), 0.0);
    // A zero normal has no tangent plane.
    EXPECT_EQ(pointToPolygonFormFactor(p, Vec3(0.0f), rectangle({0, 0, 1}, {1, 0, 0}, {0, 1, 0})),
              0.0);
    // A repeated vertex changes nothing.
    const std::vector<Vec3> triangle = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    const std::vector<Vec3> repeated = {{0, 0, 1}, {1, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    EXPECT_NEAR(pointToPolygonFormFactor(p, n, repeated), pointToPolygonFormFactor(p, n, triangle),
                1e-12);
}

TEST(PointToPolygon, FiniteAndAccurateCloseToTheBoundary) {
    const Vec3 n(0, 0, 1);
    // Approaching a corner of a parallel rectangle: exact down to tiny distances, tending to 1/4.
    for (float c : {1e-2f, 1e-4f, 1e-6f}) {
        const auto polygon = rectangle({0, 0, c}, {1, 0, 0}, {0, 1, 0});
        expectRelative(pointToPolygonFormFactor(Vec3(0.0f), n, polygon),
                       parallelRectangleCorner(1, 1, c), 1e-5);
    }
    // A perpendicular rectangle whose bottom edge passes close to p: tends to 1/4.
    for (float c : {1e-2f, 1e-4f, 1e-6f}) {
        const auto polygon = rectangle({0, c, 0}, {1, 0, 0}, {0, 0, 1});
        expectRelative(pointToPolygonFormFactor(Vec3(0.0f), n, polygon),
                       perpendicularRectangleCorner(1, 1, c), 1e-5);
    }
    // Exactly degenerate positions: finite values in [0, 1].
    const auto perpendicular = rectangle({0, 0, 0}, {1, 0, 0}, {0, 0, 1});
    const auto tilted = rectangle({-1, -1, 0}, {2, 0, 0}, {0, 2, 1});
    const auto tangent = rectangle({-1, -1, 0}, {2, 0, 0}, {0, 2, 0});
    struct Case {
        const char* name;
        Vec3 p;
        std::vector<Vec3> polygon;
    };
    for (const Case& c : {Case{"p at a vertex", {0, 0, 0}, perpendicular},
                          Case{"p on an edge", {0.5f, 0, 0}, perpendicular},
                          Case{"p inside a tilted polygon", {0, 0, 0.5f}, tilted},
                          Case{"p on the edge of a tilted polygon", {0, -1, 0}, tilted},
                          Case{"polygon in the tangent plane", {0, 0, 0}, tangent},
                          Case{"polygon in the tangent plane, p outside", {5, 0, 0}, tangent}}) {
        const double f = pointToPolygonFormFactor(c.p, n, c.polygon);
        EXPECT_TRUE(std::isfinite(f)) << c.name;
        EXPECT_GE(f, 0.0) << c.name;
        EXPECT_LE(f, 1.0) << c.name;
    }
    EXPECT_EQ(pointToPolygonFormFactor({0, 0, 0}, n, tangent), 0.0);
}

TEST(AreaToArea, ParallelOpposedRectangles) {
    // Order 8 is within 0.5 % down to a separation c of 1/20 of the shorter side (X = 60, Y = 20:
    // 0.2 %); c = 1/50 of it needs order 10, 1/100 order 12 (measured).
    struct Case {
        float a, b, c;
        int order;
    };
    for (const Case& k : {Case{1, 1, 2, 4}, Case{1, 1, 1, 4}, Case{1, 2, 1, 4}, Case{3, 1, 0.5f, 8},
                          Case{1, 1, 0.25f, 8}, Case{1, 2, 0.1f, 8}, Case{1, 1, 0.05f, 8},
                          Case{3, 1, 0.05f, 8}, Case{1, 1, 0.01f, 12}}) {
        SCOPED_TRACE(testing::Message()
                     << "a " << k.a << " b " << k.b << " c " << k.c << " order " << k.order);
        const auto from = rectangle({0, 0, 0}, {k.a, 0, 0}, {0, k.b, 0});
        const auto to = rectangle({0, 0, k.c}, {0, k.b, 0}, {k.a, 0, 0});
        expectRelative(areaToAreaFormFactor(from, to, k.order), opposedRectangles(k.a, k.b, k.c),
                       kCatalogueTolerance);
    }
}

TEST(AreaToArea, PerpendicularRectanglesSharingAnEdge) {
    // The adjacent, singular case; no subdivision is needed. The order needed for 0.5 % grows with
    // the emitter's depth W against the receiver's height H (measured): 2 for W = H = 1, at most 5
    // for W <= 1 and W / H <= 5, 8 for W / H <= 5 up to W = 10, 7 to 9 for W / H = 10, 11 to 15
    // for W / H = 50.
    const float l = 1.0f;
    struct Case {
        float w, h;
        int order;
    };
    for (const Case& k :
         {Case{1, 1, 2}, Case{0.1f, 0.1f, 5}, Case{0.2f, 1, 5}, Case{1, 0.2f, 5}, Case{0.2f, 5, 5},
          Case{1, 5, 5}, Case{5, 1, 8}, Case{5, 5, 8}, Case{10, 10, 8}, Case{5, 0.1f, 16}}) {
        SCOPED_TRACE(testing::Message() << "w " << k.w << " h " << k.h << " order " << k.order);
        const auto from = rectangle({0, 0, 0}, {k.w, 0, 0}, {0, l, 0});
        const auto to = rectangle({0, 0, 0}, {0, l, 0}, {0, 0, k.h});
        expectRelative(areaToAreaFormFactor(from, to, k.order),
                       perpendicularRectanglesCommonEdge(k.w, k.h, l), kCatalogueTolerance);
    }
}

TEST(AreaToArea, CoaxialParallelDiscs) {
    // Discs as regular 64-gons of the discs' areas: the polygonisation error is below 1e-6 (3e-6
    // at 32 sides). The emitting disc is a fan of triangles around its centre, as a mesh would be.
    constexpr int kSides = 64;
    for (float r2 : {0.5f, 1.0f, 2.0f})
        for (float h : {0.5f, 1.0f, 2.0f}) {
            SCOPED_TRACE(testing::Message() << "r2 " << r2 << " h " << h);
            const auto from = discPolygon(1.0, 0.0, kSides, false);
            const auto to = discPolygon(r2, h, kSides, true);
            double weighted = 0.0, area = 0.0;
            for (int i = 0; i < kSides; ++i) {
                const std::vector<Vec3> triangle = {Vec3(0.0f), from[i], from[(i + 1) % kSides]};
                const double a = polygonArea(triangle);
                weighted += a * areaToAreaFormFactor(triangle, to, 8);
                area += a;
            }
            expectRelative(weighted / area, coaxialDiscs(1.0, r2, h), kCatalogueTolerance);
        }
}

// Triangle with its front turned towards `target`.
std::vector<Vec3> facing(std::vector<Vec3> triangle, const Vec3& target) {
    const Vec3 normal = glm::cross(triangle[1] - triangle[0], triangle[2] - triangle[0]);
    if (glm::dot(normal, target - triangle[0]) < 0.0f)
        std::swap(triangle[1], triangle[2]);
    return triangle;
}

Vec3 centroid(const std::vector<Vec3>& polygon) {
    Vec3 sum(0.0f);
    for (const Vec3& v : polygon)
        sum += v;
    return sum / float(polygon.size());
}

void expectReciprocal(const std::vector<Vec3>& i, const std::vector<Vec3>& j, int order) {
    const double aij = polygonArea(i) * areaToAreaFormFactor(i, j, order);
    const double aji = polygonArea(j) * areaToAreaFormFactor(j, i, order);
    EXPECT_NEAR(aij, aji, 0.01 * std::max(aij, aji));
}

TEST(AreaToArea, ReciprocityForRandomTrianglePairs) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const auto randomPoint = [&](float zLo) { return Vec3(u(rng), u(rng), zLo + u(rng)); };
    int nonZero = 0;
    for (int pair = 0; pair < 50; ++pair) {
        SCOPED_TRACE(testing::Message() << "pair " << pair);
        // Separate slabs so that the triangles cannot intersect; they may still cross each
        // other's planes, which the one-sided clipping must handle symmetrically.
        std::vector<Vec3> i = {randomPoint(0.0f), randomPoint(0.0f), randomPoint(0.0f)};
        std::vector<Vec3> j = {randomPoint(1.2f), randomPoint(1.2f), randomPoint(1.2f)};
        i = facing(i, centroid(j));
        j = facing(j, centroid(i));
        expectReciprocal(i, j, 8);
        nonZero += areaToAreaFormFactor(i, j, 8) > 0.0;
    }
    EXPECT_GT(nonZero, 40);
}

TEST(AreaToArea, ReciprocityForAdjacentTriangles) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int pair = 0; pair < 20; ++pair) {
        SCOPED_TRACE(testing::Message() << "pair " << pair);
        // Shared edge on the x axis; the apices on either side, at dihedral angles below 180
        // degrees so that the triangles face each other.
        const Vec3 a(0, 0, 0), b(1.0f + 0.5f * u(rng), 0, 0);
        const Vec3 apexI(0.5f * u(rng) + 0.5f, 0.5f + 0.4f * u(rng), 0.1f + 0.05f * u(rng));
        const Vec3 apexJ(0.5f * u(rng) + 0.5f, 0.1f + 0.05f * u(rng), 0.5f + 0.4f * u(rng));
        const auto i = facing({a, b, apexI}, apexJ);
        const auto j = facing({a, b, apexJ}, apexI);
        ASSERT_GT(areaToAreaFormFactor(i, j, 8), 0.0);
        expectReciprocal(i, j, 8);
    }
}

// The six faces of the unit cube, facing inwards, each split into 2 x 2 quads (or each quad into
// two triangles).
std::vector<std::vector<Vec3>> cubeElements(bool triangles) {
    std::vector<std::vector<Vec3>> elements;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            Vec3 o(0.0f), u(0.0f), v(0.0f);
            o[axis] = float(side);
            u[(axis + 1) % 3] = 0.5f;
            v[(axis + 2) % 3] = 0.5f;
            // u x v points along +axis: inwards on side 0, outwards on side 1.
            if (side == 1)
                std::swap(u, v);
            for (int s = 0; s < 2; ++s)
                for (int t = 0; t < 2; ++t) {
                    const auto quad = rectangle(o + float(s) * u + float(t) * v, u, v);
                    if (triangles) {
                        elements.push_back({quad[0], quad[1], quad[2]});
                        elements.push_back({quad[0], quad[2], quad[3]});
                    } else {
                        elements.push_back(quad);
                    }
                }
        }
    return elements;
}

TEST(AreaToArea, ClosedCubeRowsSumToOne) {
    // Each quadrature point sees the whole closed cube, so its row of point-to-polygon form
    // factors sums to 1 exactly and the row sums hold to rounding at any order: this checks the
    // clipping, the one-sidedness and coplanar pairs (zero), not the quadrature.
    for (bool triangles : {false, true}) {
        const auto elements = cubeElements(triangles);
        for (size_t i = 0; i < elements.size(); ++i) {
            double sum = 0.0;
            for (size_t j = 0; j < elements.size(); ++j)
                sum += areaToAreaFormFactor(elements[i], elements[j], 8);
            EXPECT_NEAR(sum, 1.0, kCatalogueTolerance) << (triangles ? "triangle " : "quad ") << i;
        }
    }
}

TEST(AreaToArea, BothPolygonsAreOneSided) {
    const auto from = rectangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    const auto to = rectangle({0, 0, 1}, {0, 1, 0}, {1, 0, 0});
    const double f = areaToAreaFormFactor(from, to, 4);
    EXPECT_GT(f, 0.0);
    EXPECT_EQ(areaToAreaFormFactor(from, reversed(to), 4), 0.0);
    EXPECT_EQ(areaToAreaFormFactor(reversed(from), to, 4), 0.0);
    // `to` crossing the plane of `from`, and `from` crossing the plane of `to`: two-sided is the
    // sum over both sides, and the one-sided parts are reciprocal.
    const auto tilted = rectangle({0.2f, -0.5f, -0.5f}, {0, 1, 0}, {0.3f, 0, 1.5f});
    const double front = areaToAreaFormFactor(from, tilted, 8);
    const double back = areaToAreaFormFactor(from, reversed(tilted), 8);
    EXPECT_GT(front, 0.0);
    EXPECT_GT(back, 0.0);
    expectReciprocal(from, tilted, 8);
    expectReciprocal(from, reversed(tilted), 8);
    // Coplanar polygons do not see each other.
    EXPECT_EQ(areaToAreaFormFactor(from, rectangle({1, 0, 0}, {1, 0, 0}, {0, 1, 0}), 4), 0.0);
}

TEST(AreaToArea, DegenerateInputs) {
    const auto quad = rectangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    const std::vector<Vec3> collinear = {{0, 0, 1}, {1, 0, 1}, {2, 0, 1}};
    EXPECT_EQ(areaToAreaFormFactor(quad, collinear, 4), 0.0);
    EXPECT_EQ(areaToAreaFormFactor(collinear, quad, 4), 0.0);
    EXPECT_THROW(areaToAreaFormFactor(quad, quad, 0), std::invalid_argument);
}

TEST(DiskApproximation, ExactOnTheAxisOfADisc) {
    // A differential area on the axis of a parallel disc of radius r at height h sees
    // F = r^2 / (r^2 + h^2) (Howell, section B).
    for (double h : {0.1, 1.0, 10.0}) {
        const double r = 0.7, area = pi * r * r;
        expectRelative(
            diskApproximationFormFactor({0, 0, 0}, {0, 0, 1}, {0, 0, float(h)}, {0, 0, -1}, area),
            r * r / (r * r + h * h), 1e-6);
    }
}

TEST(DiskApproximation, TendsToTheExactValueInTheFarField) {
    // A unit square tilted by 30 degrees, seen off-axis: the estimate's relative error falls as
    // A / r^2 (measured -2.6 %, -0.65 %, -0.16 % at r = 4, 8, 16).
    const Vec3 n(0, 0, 1);
    const float s = std::sin(float(pi) / 6), c = std::cos(float(pi) / 6);
    for (float distance : {4.0f, 8.0f, 16.0f}) {
        const Vec3 centre = distance * glm::normalize(Vec3(0.5f, 0.2f, 1.0f));
        const Vec3 u(1, 0, 0), v(0, -c, -s);
        const auto square = rectangle(centre - 0.5f * u - 0.5f * v, u, v);
        const Vec3 normal = glm::normalize(glm::cross(u, v));
        const double exact = pointToPolygonFormFactor({0, 0, 0}, n, square);
        const double estimate = diskApproximationFormFactor({0, 0, 0}, n, centre, normal, 1.0);
        EXPECT_NEAR(estimate, exact, 0.5 / (distance * distance) * exact)
            << "distance " << distance;
    }
    // Facing away at either end: nothing.
    EXPECT_EQ(diskApproximationFormFactor({0, 0, 0}, n, {0, 0, 2}, {0, 0, 1}, 1.0), 0.0);
    EXPECT_EQ(diskApproximationFormFactor({0, 0, 0}, -n, {0, 0, 2}, {0, 0, -1}, 1.0), 0.0);
}

}  // namespace
}  // namespace penumbra
