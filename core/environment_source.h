// Reading an environment light's image (core/environment_light.h) from a file: any format
// OpenImageIO reads, linear values (an EXR or a Radiance .hdr; an 8-bit file is read as its
// encoded values over 255, not decoded from sRGB).
#pragma once

#include "core/scene_description.h"

#include <string>

namespace penumbra {

// Reads `file` and checks it. Throws ImageIoError ("FILE: ...") when it cannot be read, and
// InputError ("FILE: pixel (x, y) channel C: ...") for a value that is not a finite radiance >= 0;
// std::invalid_argument for a scale that is not finite and > 0 (the callers check their own).
EnvironmentDesc readEnvironment(const std::string& file, float scale, const Mat3& worldToLocal);

}  // namespace penumbra
