#include "core/texture.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

Texture::Texture(std::string name, int width, int height, std::vector<Vec4> texels, WrapMode wrapS,
                 WrapMode wrapT)
    : name_(std::move(name)),
      width_(width),
      height_(height),
      texels_(std::move(texels)),
      wrapS_(wrapS),
      wrapT_(wrapT),
      average_(0.0f) {
    glm::dvec4 sum(0.0);
    for (const Vec4& t : texels_)
        sum += glm::dvec4(t);
    if (!texels_.empty())
        average_ = Vec4(sum / static_cast<double>(texels_.size()));
}

namespace {

int wrapIndex(int i, int n, WrapMode mode) {
    switch (mode) {
        case WrapMode::ClampToEdge:
            return glm::clamp(i, 0, n - 1);
        case WrapMode::MirroredRepeat: {
            const int period = 2 * n;
            int m = i % period;
            if (m < 0)
                m += period;
            return m < n ? m : period - 1 - m;
        }
        case WrapMode::Repeat:
        default: {
            int m = i % n;
            return m < 0 ? m + n : m;
        }
    }
}

// Brings a texel index into int range without changing what it addresses: modulo twice the
// size (a period of both repeat modes), or clamped just outside the edges.
int reduceIndex(double index, int n, WrapMode mode) {
    if (mode == WrapMode::ClampToEdge)
        return static_cast<int>(std::clamp(index, -1.0, double(n)));
    const double period = 2.0 * n;
    return static_cast<int>(index - period * std::floor(index / period));
}

}  // namespace

Vec4 Texture::texel(int x, int y) const {
    return texels_[static_cast<size_t>(wrapIndex(y, height_, wrapT_)) * width_ +
                   wrapIndex(x, width_, wrapS_)];
}

Vec4 Texture::sample(Vec2 uv) const {
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
        return texel(0, 0);
    // Texel centres sit at half-integer coordinates; keep the fractional part in double so
    // large repeat counts do not lose precision.
    const double x = static_cast<double>(uv.x) * width_ - 0.5;
    const double y = static_cast<double>(uv.y) * height_ - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const float tx = static_cast<float>(x - fx), ty = static_cast<float>(y - fy);
    const int x0 = reduceIndex(fx, width_, wrapS_), y0 = reduceIndex(fy, height_, wrapT_);
    return (1 - tx) * (1 - ty) * texel(x0, y0) + tx * (1 - ty) * texel(x0 + 1, y0) +
           (1 - tx) * ty * texel(x0, y0 + 1) + tx * ty * texel(x0 + 1, y0 + 1);
}

float srgbToLinear(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float linearToSrgb(float v) {
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

Vec2 TextureTransform::apply(Vec2 uv) const {
    const float c = std::cos(rotation), s = std::sin(rotation);
    const Vec2 scaled = uv * scale;
    // The extension's rotation matrix [[c, s], [-s, c]] applied to column vectors.
    return Vec2(c * scaled.x + s * scaled.y, -s * scaled.x + c * scaled.y) + offset;
}

}  // namespace penumbra
