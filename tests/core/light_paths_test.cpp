// Light-path sets (core/light_paths.h): membership against hand-checked words, the set
// algebra against the identities it must obey, and the partitions the pipelines rely on.
#include "core/light_paths.h"
#include "core/path_components.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace penumbra {
namespace {

TEST(LightPaths, MembershipFollowsTheExpression) {
    const PathSet caustics = PathSet::parse("L S+ D S* E");
    EXPECT_TRUE(caustics.contains("LSDE"));
    EXPECT_TRUE(caustics.contains("L S S D S E"));
    EXPECT_FALSE(caustics.contains("LDE"));
    EXPECT_FALSE(caustics.contains("LSDDE"));
    EXPECT_FALSE(caustics.contains("LSD"));

    const PathSet optional = PathSet::parse("L D? E");
    EXPECT_TRUE(optional.contains("LE"));
    EXPECT_TRUE(optional.contains("LDE"));
    EXPECT_FALSE(optional.contains("LDDE"));

    const PathSet alternation = PathSet::parse("L(D|S)*E");
    EXPECT_TRUE(alternation.contains("LE"));
    EXPECT_TRUE(alternation.contains("LDSDSSE"));
    EXPECT_FALSE(alternation.contains("LVE"));
    EXPECT_FALSE(alternation.contains("LDXE"));
}

TEST(LightPaths, EmptyExpressionIsTheEmptySet) {
    EXPECT_TRUE(PathSet::parse("").empty());
    EXPECT_TRUE(PathSet::parse("   ").empty());
    EXPECT_FALSE(PathSet::parse("()").empty());  // the empty word
    EXPECT_TRUE(PathSet::parse("()").contains(""));
}

TEST(LightPaths, ShortestPathIsShortestThenInAlphabetOrder) {
    EXPECT_EQ(PathSet::parse("L S+ D S* E").shortestPath(), "L S D E");
    EXPECT_EQ(PathSet::parse("L (S|D) E").shortestPaths(3),
              (std::vector<std::string>{"L D E", "L S E"}));
    EXPECT_EQ(PathSet::parse("L D* E").shortestPaths(3),
              (std::vector<std::string>{"L E", "L D E", "L D D E"}));
    EXPECT_EQ(PathSet::parse("").shortestPath(), std::nullopt);
}

TEST(LightPaths, SetAlgebraIdentities) {
    const PathSet all = PathSet::parse("L(D|S)*E");
    const PathSet a = PathSet::parse("L S* D S* E");
    const PathSet b = PathSet::parse("L D+ S* D S* E");
    // Disjoint: a has exactly one D, b at least two.
    EXPECT_TRUE((a & b).empty());
    EXPECT_FALSE((a | b).empty());
    // x - x is empty, x & x = x, (all - a) and a partition all.
    EXPECT_TRUE((a - a).empty());
    EXPECT_TRUE(((a & a) - a).empty());
    EXPECT_TRUE((a - (a & a)).empty());
    const PathSet rest = all - a;
    EXPECT_TRUE((rest & a).empty());
    EXPECT_TRUE((all - (rest | a)).empty());
    EXPECT_TRUE(((rest | a) - all).empty());
    // A word of `all` is in exactly one of a and rest.
    for (const char* word : {"LE", "LDE", "LSDE", "LDDE", "LSDDSE", "LSSE"})
        EXPECT_NE(a.contains(word), rest.contains(word)) << word;
}

TEST(LightPaths, OverlapIsNamedByAShortestCommonPath) {
    // Plain path tracing and a caustic pass both count the caustic paths.
    const PathSet path = PathSet::parse("L(D|S)*E");
    const PathSet caustics = PathSet::parse("LS+DS*E");
    EXPECT_EQ((path & caustics).shortestPath(), "L S D E");
}

TEST(LightPaths, HybridPartitionLeavesOnlyIndirectCaustics) {
    // The hybrid pipeline (docs/light-paths.md): the path tracer counts emission seen through
    // specular chains, direct light at the first diffuse vertex and, at each later diffuse
    // vertex, the radiosity solution's L D+ and the light arriving through specular chains
    // (L S+ D, and the same again behind them); the caustic pass counts L S+ D S* E.
    const PathSet path = PathSet::parse("L S* E | L D S* E | (L D+ | L S+ D) (S+ D)* S* D S* E");
    const PathSet caustics = PathSet::parse("L S+ D S* E");
    const PathSet all = PathSet::parse("L(D|S)*E");
    EXPECT_TRUE((path & caustics).empty());
    const PathSet missing = all - (path | caustics);
    EXPECT_EQ(missing.shortestPaths(2), (std::vector<std::string>{"L S D D D E", "L D S D D D E"}));
    // With the caustic photons in the solution (the preset's order: caustics, radiosity, path),
    // the second diffuse vertex also receives L S+ D+.
    const PathSet fed = PathSet::parse("L S* E | L D S* E | L S* D+ (S+ D)* S* D S* E");
    EXPECT_TRUE((fed & caustics).empty());
    EXPECT_EQ((all - (fed | caustics)).shortestPaths(2),
              (std::vector<std::string>{"L D S D D D E", "L D D S D D D E"}));
}

TEST(LightPaths, MalformedExpressionsNameThePosition) {
    for (const char* bad : {"L(D", "LD)", "LXE", "L|*", "*L", "L D (", "L ? ?("}) {
        try {
            PathSet::parse(bad);
            ADD_FAILURE() << "accepted " << bad;
        } catch (const PathExpressionError& e) {
            EXPECT_NE(std::string(e.what()).find("at position"), std::string::npos) << e.what();
        }
    }
    try {
        PathSet::parse("LXE");
    } catch (const PathExpressionError& e) {
        EXPECT_NE(std::string(e.what()).find("position 1: unexpected character 'X'"),
                  std::string::npos)
            << e.what();
    }
}

// The light-path components (core/path_components.h) partition every path: pairwise disjoint,
// together L (D|S)* E, so that component layers sum to the beauty whatever the passes count.
TEST(LightPaths, ComponentsPartitionEveryPath) {
    std::vector<PathSet> components;
    for (const std::string_view expression : kPathComponentPaths)
        components.push_back(PathSet::parse(expression));
    PathSet together = PathSet::parse("");
    for (size_t a = 0; a < components.size(); ++a) {
        for (size_t b = a + 1; b < components.size(); ++b)
            EXPECT_TRUE((components[a] & components[b]).empty()) << a << " and " << b;
        together = together | components[a];
    }
    const PathSet all = PathSet::parse("L(D|S)*E");
    EXPECT_TRUE((all - together).empty());
    EXPECT_TRUE((together - all).empty());
}

// pathComponent(), which the estimators file their contributions by, names the component whose
// expression holds the path: every path of up to six scattering vertices.
TEST(LightPaths, PathComponentAgreesWithTheExpressions) {
    for (int vertices = 0; vertices <= 6; ++vertices) {
        for (int bits = 0; bits < (1 << vertices); ++bits) {
            // Vertex i from the eye is specular where bit i is set; the word runs light to eye.
            std::string path = "L";
            for (int i = vertices - 1; i >= 0; --i)
                path += (bits >> i) & 1 ? 'S' : 'D';
            path += 'E';
            const PathComponent component = pathComponent(vertices, (bits & 1) != 0);
            for (size_t c = 0; c < kPathComponentCount; ++c) {
                EXPECT_EQ(PathSet::parse(kPathComponentPaths[c]).contains(path),
                          c == static_cast<size_t>(component))
                    << path << " in " << kPathComponentNames[c];
            }
        }
    }
}

}  // namespace
}  // namespace penumbra
