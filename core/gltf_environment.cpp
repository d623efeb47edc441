// The environment light a converted scene records in its scene's `extras`: Mitsuba 0.5's envmap
// as ../shared/scenes' converter writes it (`mitsuba_environment`: the image file relative to the
// glTF file, a scale and the map's row-major `toWorld`). Core glTF has no environment light.
#include "core/environment_source.h"
#include "core/errors.h"
#include "core/gltf_detail.h"

#include <cmath>
#include <filesystem>

namespace penumbra::gltf {

namespace {

// The rotation part of a row-major 4 x 4 matrix, checked to be a rotation (orthonormal, det +1,
// to 1e-4): its inverse is then its transpose.
Mat3 rotationOf(const Context& ctx, const std::vector<double>& m, const std::string& pointer) {
    Mat3 toWorld;
    for (int row = 0; row < 3; ++row) {
        for (int column = 0; column < 3; ++column)
            toWorld[column][row] = static_cast<float>(m[size_t(4 * row + column)]);
    }
    const Mat3 product = glm::transpose(toWorld) * toWorld;
    float error = std::abs(glm::determinant(toWorld) - 1.0f);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
            error = std::max(error, std::abs(product[i][j] - (i == j ? 1.0f : 0.0f)));
    }
    if (!(error < 1e-4f))
        ctx.fail(pointer, "must be a rotation (penumbra does not scale or mirror environments)");
    return toWorld;
}

}  // namespace

std::optional<EnvironmentDesc> readSceneEnvironment(const Context& ctx, int scene) {
    const tinygltf::Value& extras = ctx.model.scenes[size_t(scene)].extras;
    if (!extras.IsObject() || !extras.Has("mitsuba_environment"))
        return std::nullopt;
    const std::string p = at("scenes", size_t(scene)) + "/extras/mitsuba_environment";
    const tinygltf::Value& list = extras.Get("mitsuba_environment");
    if (!list.IsArray() || list.ArrayLen() == 0)
        ctx.fail(p, "expected an array of one envmap record");
    if (list.ArrayLen() > 1)
        ctx.fail(p, "penumbra takes one environment light, not " + std::to_string(list.ArrayLen()));
    const tinygltf::Value& record = list.Get(0);
    const std::string r = p + "/0";
    if (!record.IsObject())
        ctx.fail(r, "expected an object");
    const tinygltf::Value& type = record.Get("type");
    if (!type.IsString() || type.Get<std::string>() != "envmap")
        ctx.fail(r + "/type", "must be \"envmap\"");
    const tinygltf::Value& file = record.Get("file");
    if (!file.IsString() || file.Get<std::string>().empty())
        ctx.fail(r + "/file", "expected the image's path, relative to the glTF file");
    const double scale = numberOr(ctx, record, "scale", 1.0, r);
    if (!(std::isfinite(scale) && scale > 0.0))
        ctx.fail(r + "/scale", "must be greater than 0");
    const std::vector<double> identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const Mat3 toWorld = rotationOf(ctx, numbersOr(ctx, record, "toWorld_rowmajor", identity, r),
                                    r + "/toWorld_rowmajor");
    const std::filesystem::path image =
        std::filesystem::path(ctx.file).parent_path() / file.Get<std::string>();
    try {
        return readEnvironment(image.string(), static_cast<float>(scale), glm::transpose(toWorld));
    } catch (const InputError& e) {
        ctx.fail(r + "/file", e.what());
    }
}

}  // namespace penumbra::gltf
