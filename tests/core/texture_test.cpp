// Texture lookups: bilinear filtering, the glTF wrap modes and KHR_texture_transform.
#include "core/texture.h"

#include <gtest/gtest.h>

namespace penumbra {
namespace {

// A 2 x 1 texture: black on the left texel, white on the right one.
Texture blackWhite(WrapMode wrap) {
    return Texture("bw", 2, 1, {Vec4(0.0f), Vec4(1.0f)}, wrap, WrapMode::ClampToEdge);
}

TEST(Texture, BilinearFilteringHitsTexelCentresExactlyAndInterpolatesBetween) {
    const Texture t = blackWhite(WrapMode::ClampToEdge);
    // Texel centres at u = 0.25 and 0.75.
    EXPECT_FLOAT_EQ(t.sample({0.25f, 0.5f}).r, 0.0f);
    EXPECT_FLOAT_EQ(t.sample({0.75f, 0.5f}).r, 1.0f);
    EXPECT_FLOAT_EQ(t.sample({0.5f, 0.5f}).r, 0.5f);
}

TEST(Texture, WrapModesFollowTheGltfSampler) {
    // At u = 0 the footprint straddles the left edge: halfway between texel 0 and the texel
    // that the wrap mode puts at index -1.
    EXPECT_FLOAT_EQ(blackWhite(WrapMode::ClampToEdge).sample({0.0f, 0.5f}).r, 0.0f);
    EXPECT_FLOAT_EQ(blackWhite(WrapMode::Repeat).sample({0.0f, 0.5f}).r, 0.5f);
    EXPECT_FLOAT_EQ(blackWhite(WrapMode::MirroredRepeat).sample({0.0f, 0.5f}).r, 0.0f);
    // Repeat is periodic, also far from the unit square.
    EXPECT_FLOAT_EQ(blackWhite(WrapMode::Repeat).sample({1000.75f, 0.5f}).r, 1.0f);
    EXPECT_FLOAT_EQ(blackWhite(WrapMode::Repeat).sample({-999.75f, 0.5f}).r, 0.0f);
    // Mirrored repeat reverses every other period: u = 1.25 mirrors to 0.75.
    EXPECT_FLOAT_EQ(blackWhite(WrapMode::MirroredRepeat).sample({1.25f, 0.5f}).r, 1.0f);
    EXPECT_FLOAT_EQ(blackWhite(WrapMode::MirroredRepeat).sample({1.75f, 0.5f}).r, 0.0f);
}

TEST(Texture, NonFiniteCoordinatesGiveATexelNotNaN) {
    const Texture t = blackWhite(WrapMode::Repeat);
    EXPECT_TRUE(std::isfinite(t.sample({NAN, 0.5f}).r));
}

TEST(Texture, AverageIsTheTexelMean) {
    EXPECT_FLOAT_EQ(blackWhite(WrapMode::Repeat).average().r, 0.5f);
}

TEST(TextureTransform, AppliesScaleThenRotationThenOffset) {
    // KHR_texture_transform README example: offset (0.5, 0), rotation pi/2, scale (2, 2)
    // maps (1, 0) to T R S (1, 0) = (0.5, 0) + R (2, 0) = (0.5, -2) with R = [[c, s], [-s, c]].
    const TextureTransform transform{{0.5f, 0.0f}, kPi / 2.0f, {2.0f, 2.0f}};
    const Vec2 uv = transform.apply({1.0f, 0.0f});
    EXPECT_NEAR(uv.x, 0.5f, 1e-6f);
    EXPECT_NEAR(uv.y, -2.0f, 1e-6f);
}

TEST(SrgbTransfer, DecodeAndEncodeAreInversesAndMatchKnownValues) {
    // IEC 61966-2-1: 0.5 encoded is 0.21404 linear; the linear segment below 0.04045.
    EXPECT_NEAR(srgbToLinear(0.5f), 0.214041f, 1e-5f);
    EXPECT_FLOAT_EQ(srgbToLinear(0.02f), 0.02f / 12.92f);
    for (float v : {0.0f, 0.001f, 0.2f, 0.5f, 1.0f}) {
        EXPECT_NEAR(linearToSrgb(srgbToLinear(v)), v, 1e-5f);
    }
}

}  // namespace
}  // namespace penumbra
