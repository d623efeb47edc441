#include "passes/pass.h"

#include <stdexcept>

namespace penumbra {

void PassContext::addToLayer(const std::string& name, const Image& image) {
    const auto it = layers.find(name);
    if (it == layers.end()) {
        layers[name] = image;
        return;
    }
    Image& sum = it->second;
    if (sum.width() != image.width() || sum.height() != image.height() ||
        sum.channels() != image.channels()) {
        throw std::logic_error("layer " + name + ": an image of another size or channels");
    }
    const auto in = image.pixels();
    auto out = sum.pixels();
    for (size_t i = 0; i < out.size(); ++i)
        out[i] += in[i];
}

}  // namespace penumbra
