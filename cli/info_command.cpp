// `penumbra info SCENE`: what a scene contains and how penumbra reads it.
#include "cli/commands.h"
#include "cli/scene_input.h"
#include "core/light_groups.h"
#include "core/scene.h"
#include "passes/pipeline.h"

#include <iostream>
#include <map>

namespace penumbra::cli {

namespace {

void printInfo(const Scene& scene) {
    const SceneDescription& desc = scene.description();
    std::map<std::string, int> lightCounts;
    for (const auto& light : scene.lights()) {
        switch (light->kind()) {
            case LightKind::Point:
                ++lightCounts["point"];
                break;
            case LightKind::Spot:
                ++lightCounts["spot"];
                break;
            case LightKind::Directional:
                ++lightCounts["directional"];
                break;
            case LightKind::Area:
                ++lightCounts["emissive triangles"];
                break;
            case LightKind::Environment:
                ++lightCounts["environment"];
                break;
            case LightKind::Goniometric:
                ++lightCounts["goniometric (IES, EULUMDAT)"];
                break;
        }
    }
    size_t emissiveMaterials = 0;
    for (const Material& m : desc.materials)
        emissiveMaterials += m.isEmissive() ? 1 : 0;

    std::cout << "scene:      " << desc.file << "\n"
              << "meshes:     " << desc.meshes.size() << " primitive instances\n"
              << "triangles:  " << scene.triangleCount() << "\n"
              << "materials:  " << desc.materials.size() << " (" << emissiveMaterials
              << " emissive)\n"
              << "textures:   " << desc.textures.size() << "\n"
              << "cameras:    " << desc.cameras.size();
    for (const CameraDesc& camera : desc.cameras)
        std::cout << " '" << camera.name << "'";
    std::cout << "\nlights:     " << scene.lights().size();
    for (const auto& [kind, count] : lightCounts)
        std::cout << ", " << count << " " << kind;
    // The layers `render --light-groups` would write.
    std::cout << "\nlight groups:";
    for (const LightGroup& group : lightGroups(desc))
        std::cout << " " << group.name;
    const Bounds3& b = scene.bounds();
    std::cout << "\nbounds:     (" << b.lo.x << ", " << b.lo.y << ", " << b.lo.z << ") to ("
              << b.hi.x << ", " << b.hi.y << ", " << b.hi.z << ") m, relative to (" << desc.origin.x
              << ", " << desc.origin.y << ", " << desc.origin.z << ") in the file\n";
    if (const Medium* medium = scene.medium()) {
        const Color& sigmaS = medium->sigmaS();
        const Color sigmaA = medium->sigmaT() - sigmaS;
        const Bounds3& box = medium->box();
        std::cout << "medium:     sigma_a (" << sigmaA.r << ", " << sigmaA.g << ", " << sigmaA.b
                  << ") /m, sigma_s (" << sigmaS.r << ", " << sigmaS.g << ", " << sigmaS.b
                  << ") /m, g " << medium->phase().g() << ", in (" << box.lo.x << ", " << box.lo.y
                  << ", " << box.lo.z << ") to (" << box.hi.x << ", " << box.hi.y << ", "
                  << box.hi.z << ") m";
        if (const DensityGrid* density = medium->density())
            std::cout << ", scaled by a density grid of " << density->nodes().x << " x "
                      << density->nodes().y << " x " << density->nodes().z << " nodes, at most "
                      << density->maxValue();
        if (medium->emits()) {
            const Color& Le = medium->emission();
            std::cout << ", emitting (" << Le.r << ", " << Le.g << ", " << Le.b << ") cd/m²";
        }
        std::cout << "\n";
    }
    std::cout << "extensions: ";
    for (const std::string& e : desc.report.extensionsUsed)
        std::cout << e << " ";
    std::cout << "\nignored:    ";
    for (const std::string& e : desc.report.extensionsIgnored)
        std::cout << e << " ";
    std::cout << "\ndegenerate triangles dropped: " << desc.report.degenerateTriangles << "\n";
}

// A pass script's settings and passes, as written; the passes are built (and so checked) first.
void printScript(const PassScript& script) {
    makeScriptPipeline(script);
    std::cout << "script:     " << script.file << "\nsettings:   ";
    std::string separator;
    for (const auto& [key, value] : script.topLevel.entries()) {
        if (key == "pass")
            continue;
        std::cout << separator << key << " = " << value;
        separator = ", ";
    }
    if (script.pipeline) {
        std::cout << "\npasses:     the built-in pipeline " << *script.pipeline
                  << " (penumbra plan lists them)\n";
        return;
    }
    std::cout << "\npasses:     " << script.passes.size() << "\n";
    for (const ScriptPass& pass : script.passes) {
        std::cout << "  " << pass.parameters.path() << " (line " << pass.parameters.location().line
                  << "): " << pass.type;
        for (const auto& [key, value] : pass.parameters.entries()) {
            if (key != "type")
                std::cout << ", " << key << " = " << value;
        }
        std::cout << "\n";
    }
}

}  // namespace

Command addInfoCommand(CLI::App& app) {
    auto* command = app.add_subcommand("info",
                                       "Print what a scene contains: meshes, triangles, "
                                       "materials, lights by type, bounds, extensions");
    auto options = std::make_shared<SceneInput>();
    addSceneInputOptions(*command, *options, PassScripts::Accepted);
    return [options] {
        if (const std::optional<PassScript> script = readPassScript(*options))
            printScript(*script);
        printInfo(*loadScene(*options));
    };
}

}  // namespace penumbra::cli
