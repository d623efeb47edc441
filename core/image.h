// A float image with named channels: the resolved film, its AOV layers, and images read from
// files. Reading and writing files is in core/image_io.h.
#pragma once

#include <cassert>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace penumbra {

// width x height pixels of channels() floats each, interleaved, row-major with the top row
// first (pixel (0, 0) is the top-left corner, as on the film).
class Image {
  public:
    Image() = default;
    // Zero-filled; one channel per name (e.g. {"R", "G", "B"}, or {"Z"} for depth).
    Image(int width, int height, std::vector<std::string> channelNames)
        : width_(width), height_(height), channelNames_(std::move(channelNames)) {
        if (width < 0 || height < 0 || channelNames_.empty()) {
            throw std::invalid_argument("Image: negative size or no channels");
        }
        pixels_.assign(size_t(width) * size_t(height) * channelNames_.size(), 0.0f);
    }

    int width() const { return width_; }
    int height() const { return height_; }
    int channels() const { return int(channelNames_.size()); }
    const std::vector<std::string>& channelNames() const { return channelNames_; }

    // Index of the channel called `name`, or -1.
    int channelIndex(std::string_view name) const {
        for (size_t c = 0; c < channelNames_.size(); ++c) {
            if (channelNames_[c] == name) {
                return int(c);
            }
        }
        return -1;
    }

    float& at(int x, int y, int channel) { return pixels_[offset(x, y, channel)]; }
    float at(int x, int y, int channel) const { return pixels_[offset(x, y, channel)]; }

    // All values, interleaved: (y * width + x) * channels + channel.
    std::span<float> pixels() { return pixels_; }
    std::span<const float> pixels() const { return pixels_; }

  private:
    size_t offset(int x, int y, int channel) const {
        assert(x >= 0 && x < width_ && y >= 0 && y < height_ && channel >= 0 &&
               channel < channels());
        return (size_t(y) * size_t(width_) + size_t(x)) * channelNames_.size() + size_t(channel);
    }

    int width_ = 0, height_ = 0;
    std::vector<std::string> channelNames_;
    std::vector<float> pixels_;
};

// sum += image, pixel by pixel; std::logic_error when their sizes or channel counts differ.
inline void addPixels(Image& sum, const Image& image) {
    if (sum.width() != image.width() || sum.height() != image.height() ||
        sum.channels() != image.channels()) {
        throw std::logic_error("addPixels: an image of another size or channels");
    }
    const auto in = image.pixels();
    const auto out = sum.pixels();
    for (size_t i = 0; i < out.size(); ++i)
        out[i] += in[i];
}

}  // namespace penumbra
