#include "passes/pass.h"

namespace penumbra {

void PassContext::addToLayer(const std::string& name, const Image& image) {
    const auto it = layers.find(name);
    if (it == layers.end()) {
        layers[name] = image;
        return;
    }
    addPixels(it->second, image);
}

}  // namespace penumbra
