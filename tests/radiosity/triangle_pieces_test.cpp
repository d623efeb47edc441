// Cutting a triangle into pieces along segments (radiosity/triangle_pieces.h). The oracles are
// geometric and need no renderer: the pieces cover the triangle exactly once (their areas sum
// to its area, none inverted) and no segment passes through a piece's inside farther than the
// cut's resolution from the piece's edges.
#include "radiosity/triangle_pieces.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

namespace penumbra {
namespace {

// The pieces' areas in the plane of the triangle they cut, signed: positive for a piece that
// runs counter-clockwise as the triangle does. A point is placed by its last two barycentrics,
// c0 + b1 (c1 - c0) + b2 (c2 - c0), the affine map a piece's barycentric corners stand for:
// the three floats need not sum to 1 exactly, and on a thin triangle that rounding alone would
// move a point across it by a part in 10^5.
std::vector<double> pieceAreas(const std::array<Vec3, 3>& corners, const TrianglePieces& cut) {
    const glm::dvec3 c0(corners[0]), e1 = glm::dvec3(corners[1]) - c0,
                                     e2 = glm::dvec3(corners[2]) - c0;
    const glm::dvec3 normal = glm::normalize(glm::cross(e1, e2));
    std::vector<double> areas;
    for (const std::array<uint32_t, 3>& piece : cut.pieces) {
        std::array<glm::dvec3, 3> p;
        for (size_t c = 0; c < 3; ++c) {
            const Vec3& b = cut.points[piece[c]];
            p[c] = c0 + double(b.y) * e1 + double(b.z) * e2;
        }
        areas.push_back(0.5 * glm::dot(glm::cross(p[1] - p[0], p[2] - p[0]), normal));
    }
    return areas;
}

double triangleArea(const std::array<Vec3, 3>& corners) {
    const glm::dvec3 c0(corners[0]);
    return glm::length(glm::cross(glm::dvec3(corners[1]) - c0, glm::dvec3(corners[2]) - c0)) / 2.0;
}

float longestEdge(const std::array<Vec3, 3>& corners) {
    return std::max({glm::distance(corners[0], corners[1]), glm::distance(corners[1], corners[2]),
                     glm::distance(corners[2], corners[0])});
}

// The pieces of a triangle 5 m on a side cut by a segment and another that ends `gap` (in
// barycentric units) beside it: their signed areas in the triangle's plane.
std::vector<double> piecesBesideASegment(float gap, float resolution) {
    const std::array<Vec3, 3> corners = {Vec3(0, 0, 0), Vec3(5, 0, 0), Vec3(0, 0, -5)};
    const std::vector<TriangleSegment> segments = {
        {Vec3(0.2f, 0.6f, 0.2f), Vec3(0.6f, 0.2f, 0.2f)},
        {Vec3(0.4f, 0.4f - gap, 0.2f + gap), Vec3(0.3f, 0.3f, 0.4f)}};
    return pieceAreas(corners, cutTriangle(corners, segments, resolution));
}

TEST(TrianglePieces, AnEndPointBesideASegmentIsPutOnIt) {
    // 5e-7 m beside the first segment, under the 1-mm resolution: no sliver between them.
    for (const float gap : {1e-7f, 1e-4f}) {
        const std::vector<double> areas = piecesBesideASegment(gap, 1e-3f);
        double sum = 0.0;
        for (const double a : areas) {
            EXPECT_GT(a, 1e-4 * 12.5) << "a piece flatter than the cut's features, gap " << gap;
            sum += a;
        }
        EXPECT_NEAR(sum, 12.5, 1e-4) << "gap " << gap;
    }
    // A gap wider than the resolution is kept: the pieces between are thin but not flat.
    const std::vector<double> apart = piecesBesideASegment(1e-3f, 1e-4f);
    EXPECT_LT(*std::min_element(apart.begin(), apart.end()), 1e-2);
    EXPECT_GT(*std::min_element(apart.begin(), apart.end()), 0.0);
}

TEST(TrianglePieces, NearlyCoincidentSegmentsAcrossAThinTriangle) {
    // A wall strip of the modern hall, 4.8 m by 0.63 m, as a trial of shadow lines from the
    // area lights' corners cut it (docs/radiosity.md): four segments within a few millimetres of
    // one another, merged into one at the 3.4-cm resolution, and one crossing them at a shallow
    // angle. With Exact_intersections_tag the mesher crashed on it.
    const std::array<Vec3, 3> corners = {Vec3(-2.04502153f, 1.77202487f, -2.52968502f),
                                         Vec3(-6.82829905f, 1.1402967f, -2.52968502f),
                                         Vec3(-6.82829905f, 1.76932502f, -2.52968502f)};
    const std::vector<TriangleSegment> segments = {
        {Vec3(0.273036659f, 0.726963341f, 0.0f), Vec3(0.0f, 0.725791454f, 0.274208575f)},
        {Vec3(0.273079008f, 0.726920962f, 0.0f), Vec3(0.0f, 0.726920962f, 0.273079008f)},
        {Vec3(0.0733873546f, 0.861758769f, 0.0648538619f),
         Vec3(0.0733873546f, 0.00766411424f, 0.918948531f)},
        {Vec3(0.273036838f, 0.726963162f, 0.0f), Vec3(0.0f, 0.725791276f, 0.274208724f)},
        {Vec3(0.274947703f, 0.725052297f, 0.0f), Vec3(0.0f, 0.725052297f, 0.274947703f)}};
    const TrianglePieces cut = cutTriangle(corners, segments, 0.0337145887f);
    double sum = 0.0;
    for (const double area : pieceAreas(corners, cut))
        sum += std::abs(area);
    EXPECT_NEAR(sum, triangleArea(corners), 1e-4) << "the pieces cover it";
    EXPECT_GE(cut.pieces.size(), 3u);
}

// A triangle and the segments a cut is asked for, drawn at random: every third triangle thin
// (its third corner a thousandth to a hundredth of its length off the line of the other two),
// 2 to 12 segments, each end inside or on an edge, and half of them copies of another moved by
// 1e-7 to 1e-3 in barycentric units: the nearly coincident lines that the shadows of nearby
// sources make (docs/radiosity.md, "Contact lines").
struct RandomCut {
    std::array<Vec3, 3> corners;
    std::vector<TriangleSegment> segments;
};

RandomCut drawCut(std::mt19937& rng, bool thin) {
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const auto inCube = [&] { return Vec3(unit(rng), unit(rng), unit(rng)) * 5.0f; };
    RandomCut cut;
    cut.corners = {inCube(), inCube(), inCube()};
    if (thin) {
        const Vec3 along = cut.corners[1] - cut.corners[0];
        const Vec3 across = glm::normalize(glm::cross(along, inCube() - cut.corners[0]));
        const float height = glm::length(along) * std::pow(10.0f, -3.0f + unit(rng));
        cut.corners[2] = cut.corners[0] + unit(rng) * along + height * across;
    }
    const auto onTriangle = [&](bool onEdge) {
        Vec3 b(unit(rng), unit(rng), unit(rng));
        if (onEdge)
            b[int(unit(rng) * 2.999f)] = 0.0f;
        return b / (b.x + b.y + b.z);
    };
    const int count = 2 + int(unit(rng) * 10.999f);
    for (int s = 0; s < count; ++s) {
        if (s > 0 && unit(rng) < 0.5f) {
            const TriangleSegment& original = cut.segments[size_t(unit(rng) * float(s) * 0.999f)];
            TriangleSegment copy;
            for (int e = 0; e < 2; ++e) {
                const float shift = std::pow(10.0f, -7.0f + 4.0f * unit(rng));
                Vec3 b = original[size_t(e)] +
                         shift * (Vec3(unit(rng), unit(rng), unit(rng)) - Vec3(0.5f)) * 2.0f;
                b = glm::max(b, Vec3(0.0f));
                copy[size_t(e)] = b / (b.x + b.y + b.z);
            }
            cut.segments.push_back(copy);
        } else {
            cut.segments.push_back({onTriangle(unit(rng) < 0.5f), onTriangle(unit(rng) < 0.5f)});
        }
    }
    return cut;
}

// Whether some part of segment a-b lies inside the piece p0 p1 p2 (counter-clockwise in 2D)
// farther than `tolerance` from every one of its edges: the segment clipped to the piece shrunk
// by the tolerance (Cyrus and Beck 1978) is not empty.
bool passesThroughInside(const std::array<glm::dvec2, 3>& p, glm::dvec2 a, glm::dvec2 b,
                         double tolerance) {
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < 3; ++k) {
        const glm::dvec2 edge = p[size_t(k + 1) % 3] - p[size_t(k)];
        const double length = glm::length(edge);
        if (!(length > 0.0))
            return false;
        const glm::dvec2 inward = glm::dvec2(-edge.y, edge.x) / length;
        // Signed distance inside the shrunk edge at a + t (b - a): da + t (db - da) >= 0.
        const double da = glm::dot(a - p[size_t(k)], inward) - tolerance;
        const double db = glm::dot(b - p[size_t(k)], inward) - tolerance;
        if (da < 0.0 && db < 0.0)
            return false;
        if (da < 0.0)
            t0 = std::max(t0, da / (da - db));
        else if (db < 0.0)
            t1 = std::min(t1, da / (da - db));
    }
    return t0 < t1;
}

// The checks every cut must pass, whatever its input: points on the triangle, the pieces'
// areas summing to the triangle's with none inverted, and no segment through a piece's inside.
void expectAProperCut(const RandomCut& input, float resolution, const TrianglePieces& cut,
                      const std::string& label) {
    const double area = triangleArea(input.corners);
    for (const Vec3& b : cut.points) {
        EXPECT_GE(std::min({b.x, b.y, b.z}), 0.0f) << label;
        EXPECT_NEAR(b.x + b.y + b.z, 1.0f, 1e-5f) << label;
    }
    double sum = 0.0, inverted = 0.0;
    for (const double a : pieceAreas(input.corners, cut)) {
        sum += a;
        inverted += std::min(a, 0.0);
    }
    EXPECT_NEAR(sum, area, 1e-5 * area) << label << ": the pieces do not cover the triangle";
    EXPECT_GE(inverted, -1e-6 * area) << label << ": pieces overlap";

    // In the triangle's barycentric plane (b1, b2) scaled to metres along the longest edge: the
    // tolerance is the resolution the cut may join features within, plus float rounding.
    const double size = longestEdge(input.corners);
    const glm::dvec3 e1(input.corners[1] - input.corners[0]);
    const glm::dvec3 e2(input.corners[2] - input.corners[0]);
    const glm::dvec3 u = glm::normalize(e1), v = glm::normalize(glm::cross(glm::cross(e1, e2), e1));
    const auto toPlane = [&](const Vec3& b) {
        const glm::dvec3 q = double(b.y) * e1 + double(b.z) * e2;
        return glm::dvec2(glm::dot(q, u), glm::dot(q, v));
    };
    // A segment shorter than the resolution is a feature finer than it: its ends are merged
    // and it may vanish.
    const double joined = std::max(double(resolution), 1e-6 * size);
    const double tolerance = 2.0 * joined + 1e-5 * size;
    int straddled = 0;
    for (const std::array<uint32_t, 3>& piece : cut.pieces) {
        const std::array<glm::dvec2, 3> p = {toPlane(cut.points[piece[0]]),
                                             toPlane(cut.points[piece[1]]),
                                             toPlane(cut.points[piece[2]])};
        for (const TriangleSegment& s : input.segments) {
            const glm::dvec2 a = toPlane(s[0]), b = toPlane(s[1]);
            if (glm::distance(a, b) > joined && passesThroughInside(p, a, b, tolerance))
                ++straddled;
        }
    }
    EXPECT_EQ(straddled, 0) << label << ": pieces a segment passes through";
}

TEST(TrianglePieces, RandomCutsCoverTheTriangleAndFollowTheirSegments) {
    // At the least resolution (a millionth of the longest edge) and at a hundredth of it, which
    // joins the near copies.
    std::mt19937 rng(20261207);
    for (int trial = 0; trial < 300; ++trial) {
        const RandomCut input = drawCut(rng, trial % 3 == 0);
        for (const double fraction : {0.0, 0.01}) {
            const float resolution = float(fraction) * longestEdge(input.corners);
            const TrianglePieces cut = cutTriangle(input.corners, input.segments, resolution);
            expectAProperCut(input, resolution, cut,
                             "trial " + std::to_string(trial) + ", resolution " +
                                 std::to_string(fraction) + " of the longest edge");
        }
    }
}

}  // namespace
}  // namespace penumbra
