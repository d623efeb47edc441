#include "core/environment_source.h"

#include "core/environment_light.h"
#include "core/errors.h"
#include "core/image_io.h"

#include <cmath>
#include <stdexcept>

namespace penumbra {

EnvironmentDesc readEnvironment(const std::string& file, float scale, const Mat3& worldToLocal) {
    if (!(std::isfinite(scale) && scale > 0.0f))
        throw std::invalid_argument("readEnvironment: the scale must be finite and > 0");
    EnvironmentDesc desc;
    desc.file = file;
    desc.radiance = readImage(file);
    if (desc.radiance.width() < 1 || desc.radiance.height() < 1)
        throw InputError(file + ": the environment image has no pixels");
    const std::string bad = findBadEnvironmentPixel(desc.radiance);
    if (!bad.empty())
        throw InputError(file + ": " + bad + ": an environment's radiance must be finite and >= 0");
    desc.scale = scale;
    desc.worldToLocal = worldToLocal;
    return desc;
}

}  // namespace penumbra
