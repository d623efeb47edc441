// The luminance of an RGB image: what false colour and the `luminance` AOV show.
#pragma once

#include "core/image.h"
#include "core/math.h"

#include <stdexcept>

namespace penumbra {

// One channel "Y": the Rec. 709 luminance (core/math.h's luminance()) of channels R, G and B of
// `rgb`, in its units (cd/m² for a rendered image, lux for an illuminance layer). Throws
// std::invalid_argument when `rgb` lacks one of them.
inline Image luminanceImage(const Image& rgb, const std::string& prefix = "") {
    const int r = rgb.channelIndex(prefix + "R"), g = rgb.channelIndex(prefix + "G"),
              b = rgb.channelIndex(prefix + "B");
    if (r < 0 || g < 0 || b < 0)
        throw std::invalid_argument("luminanceImage: no channels " + prefix + "R, G, B");
    Image Y(rgb.width(), rgb.height(), {"Y"});
    for (int y = 0; y < rgb.height(); ++y) {
        for (int x = 0; x < rgb.width(); ++x)
            Y.at(x, y, 0) = luminance(Color(rgb.at(x, y, r), rgb.at(x, y, g), rgb.at(x, y, b)));
    }
    return Y;
}

}  // namespace penumbra
