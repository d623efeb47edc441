#include "cli/scene_input.h"

#include "cli/commands.h"
#include "core/environment_light.h"
#include "core/environment_source.h"
#include "core/errors.h"
#include "core/gltf_loader.h"
#include "core/photometric_files.h"
#include "core/portal_detection.h"
#include "core/sky.h"
#include "core/solar_position.h"
#include "core/vdb_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

namespace penumbra::cli {

void addSceneInputOptions(CLI::App& command, SceneInput& input, PassScripts scripts) {
    command
        .add_option("scene", input.path,
                    scripts == PassScripts::Accepted
                        ? "Scene file: .gltf or .glb, or a .toml pass script"
                        : "Scene file: .gltf or .glb")
        ->required();
    command
        .add_option("--scene-index", input.sceneIndex,
                    "Which of the file's glTF scenes to use (default: the file's `scene`)")
        ->check(atLeast(0));
    command.add_flag("-q,--quiet", input.quiet, "Print nothing but errors");
    command
        .add_option("--environment", input.environment.file,
                    "Environment light: an equirectangular image of radiance in cd/m² (EXR or "
                    ".hdr), replacing the scene's own")
        ->check(CLI::ExistingFile);
    command
        .add_option("--environment-scale", input.environment.scale,
                    "Multiplies the environment's radiance (default 1)")
        ->check(CLI::PositiveNumber);
    command
        .add_option("--environment-illuminance", input.environment.illuminance,
                    "Scales the environment so that an upward plane in the open gets this "
                    "illuminance from it, lux (instead of --environment-scale)")
        ->check(CLI::PositiveNumber);
    command.add_option("--environment-rotation", input.environment.rotationDegrees,
                       "Turns the environment about the up axis (+Y), degrees, counter-clockwise "
                       "seen from above (default 0)");
    command.add_option("--sky", input.environment.sky,
                       std::string("A sky as the environment light: ") + skyModelNames());
    command
        .add_option("--sky-illuminance", input.environment.skyIlluminance,
                    "The sky's unobstructed horizontal illuminance, lux, the ground excluded "
                    "(default 10000)")
        ->check(CLI::PositiveNumber);
    command
        .add_option("--ground-reflectance", input.environment.groundReflectance,
                    "Below the horizon a ground of luminance R E_h / pi (default 0.2)")
        ->check(CLI::Range(0.0, 1.0));
    command.add_option("--site", input.environment.site,
                       "Where the sun is seen from: LAT,LON in degrees, north and east positive");
    command.add_option("--time", input.environment.time,
                       "Local time with its UTC offset, ISO 8601: 2026-06-21T12:00+02:00");
    command.add_option("--north", input.environment.northDegrees,
                       "The angle of true north from the scene's -Z axis, degrees, "
                       "counter-clockwise seen from above (+Y) (default 0)");
    command
        .add_option("--sun-direct-normal", input.environment.sunDirectNormal,
                    "The sun's direct normal illuminance, lux: adds the sun's disc (0.53 "
                    "degrees) at the position --site and --time give")
        ->check(CLI::NonNegativeNumber);
    command
        .add_option("--portal", input.environment.portals,
                    "A window the environment is seen through, sampled to light what is behind "
                    "it: X0,Y0,Z0,X1,Y1,Z1,X2,Y2,Z2, a corner and its two neighbours (metres, "
                    "the file's world frame); repeat for several; auto: the scene's openings, "
                    "found (the default when there is an environment); none: no portal")
        ->take_all();
}

void takePipelineOption(PassScript& script, bool given, const std::string& pipeline) {
    if (!given)
        return;
    if (!script.passes.empty()) {
        throw UsageError(
            "--pipeline cannot be combined with a pass script that lists [[pass]] "
            "tables (" +
            script.file + "): they are the pipeline");
    }
    script.pipeline = pipeline;
}

std::optional<PassScript> readPassScript(SceneInput& input) {
    if (std::filesystem::path(input.path).extension() != ".toml")
        return std::nullopt;
    PassScript script = loadPassScript(input.path);
    input.path = script.scene;
    if (input.sceneIndex < 0 && script.sceneIndex)
        input.sceneIndex = *script.sceneIndex;
    // The command line's environment options win over the script's.
    const auto unlessGiven = [](auto& option, const auto& fromScript) {
        if (!option)
            option = fromScript;
    };
    EnvironmentInput& environment = input.environment;
    unlessGiven(environment.file, script.environment);
    unlessGiven(environment.scale, script.environmentScale);
    unlessGiven(environment.rotationDegrees, script.environmentRotation);
    unlessGiven(environment.illuminance, script.environmentIlluminance);
    unlessGiven(environment.sky, script.sky);
    unlessGiven(environment.skyIlluminance, script.skyIlluminance);
    unlessGiven(environment.groundReflectance, script.groundReflectance);
    unlessGiven(environment.site, script.site);
    unlessGiven(environment.time, script.time);
    unlessGiven(environment.northDegrees, script.north);
    unlessGiven(environment.sunDirectNormal, script.sunDirectNormal);
    if (environment.portals.empty())
        environment.portals = script.portals;
    input.luminaires = script.luminaires;
    input.medium = script.medium;
    return script;
}

namespace {

// The sun's place for --site and --time, in world axes.
struct SunPlace {
    Vec3 direction{0.0f, 1.0f, 0.0f};
    double zenithDegrees = 0.0;
    std::string description;  // for messages and the light's name
};

// Where --site, --time and --north put the sun; nothing without them.
std::optional<SunPlace> placeSun(const EnvironmentInput& input) {
    if (!input.site && !input.time) {
        if (input.northDegrees)
            throw UsageError("--north turns the sun's position: it needs --site and --time");
        return std::nullopt;
    }
    if (!input.site || !input.time)
        throw UsageError("--site and --time place the sun together: give both");
    SolarPosition position;
    try {
        position = solarPosition(parseSite(*input.site), parseIsoLocalTime(*input.time));
    } catch (const std::invalid_argument& e) {
        const std::string message = e.what();
        throw UsageError(message);
    }
    SunPlace sun;
    sun.direction = sunDirection(position, input.northDegrees.value_or(0.0f));
    sun.zenithDegrees = position.zenithDegrees;
    std::ostringstream text;
    text.precision(4);
    text << "sun at " << *input.site << " on " << *input.time << ": altitude "
         << 90.0 - position.zenithDegrees << " deg, azimuth " << position.azimuthDegrees << " deg";
    sun.description = text.str();
    return sun;
}

// The sun's horizontal illuminance, for the ground's glow: E_n cos Z_s.
float sunOnTheGround(const std::optional<SunDisc>& sun) {
    return sun ? sun->directNormalIlluminance * std::max(0.0f, sun->direction.y) : 0.0f;
}

// The sky of `input.sky`, with its options' defaults, and the sun's glow when it needs one.
EnvironmentDesc makeSky(const EnvironmentInput& input, const std::optional<SunPlace>& place,
                        const std::optional<SunDisc>& sun) {
    SkySettings settings;
    settings.model = *input.sky;
    settings.horizontalIlluminance = input.skyIlluminance.value_or(settings.horizontalIlluminance);
    settings.groundReflectance = input.groundReflectance.value_or(settings.groundReflectance);
    settings.sunHorizontalIlluminance = sunOnTheGround(sun);
    if (place)
        settings.sunDirection = place->direction;
    EnvironmentDesc sky;
    try {
        if (skyNeedsSun(settings.model) && !place) {
            throw UsageError("--sky " + settings.model +
                             ": this sky depends on the sun; place it with --site LAT,LON and "
                             "--time (e.g. 2026-06-21T12:00+02:00)");
        }
        sky.radiance = skyMap(settings);
    } catch (const std::invalid_argument& e) {
        const std::string message = e.what();
        throw UsageError("--sky: " + message);
    }
    std::ostringstream name;
    name << "sky " << settings.model << ", " << settings.horizontalIlluminance
         << " lux, ground reflectance " << settings.groundReflectance;
    sky.file = name.str();
    return sky;
}

// No sky and no image, only the sun: a black sky over the ground's glow of the sun's light.
EnvironmentDesc makeSunOnly(const EnvironmentInput& input, const std::optional<SunDisc>& sun) {
    constexpr int kWidth = 64, kHeight = 32;
    const float reflectance = input.groundReflectance.value_or(SkySettings{}.groundReflectance);
    const float ground = reflectance * sunOnTheGround(sun) * kInvPi;
    EnvironmentDesc desc;
    desc.radiance = Image(kWidth, kHeight, {"R", "G", "B"});
    for (int y = kHeight / 2; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            for (int c = 0; c < 3; ++c)
                desc.radiance.at(x, y, c) = ground;
    desc.file = "no sky, ground reflectance " + std::to_string(reflectance);
    return desc;
}

// The sun's disc for --sun-direct-normal at `place`.
std::optional<SunDisc> makeSun(const EnvironmentInput& input,
                               const std::optional<SunPlace>& place) {
    if (!input.sunDirectNormal)
        return std::nullopt;
    if (!place) {
        throw UsageError(
            "--sun-direct-normal needs the sun's position: --site LAT,LON and --time (e.g. "
            "2026-06-21T12:00+02:00)");
    }
    if (place->zenithDegrees >= 90.0 && *input.sunDirectNormal > 0.0f) {
        throw UsageError("--sun-direct-normal: the " + place->description +
                         " is below the horizon; it gives no direct light");
    }
    SunDisc sun;
    sun.direction = place->direction;
    sun.directNormalIlluminance = *input.sunDirectNormal;
    return sun;
}

// A portal of --portal or a script's `portals`, rebased as the scene is.
Portal parsePortal(const std::string& text, const glm::dvec3& origin) {
    try {
        const std::array<glm::dvec3, 3> c = parsePortalCorners(text);
        return Portal{Vec3(c[0] - origin), Vec3(c[1] - c[0]), Vec3(c[2] - c[0])};
    } catch (const std::invalid_argument& e) {
        const std::string message = e.what();
        throw UsageError("--" + message);
    }
}

// Scales the environment (an image's or the scene's own) so that its horizontal illuminance is
// `lux`.
void scaleToIlluminance(float lux, SceneDescription& description) {
    if (!description.environment) {
        throw UsageError(description.file +
                         ": --environment-illuminance needs an environment: the scene has none; "
                         "give one with --environment FILE");
    }
    EnvironmentDesc& environment = *description.environment;
    const EnvironmentLight map(environment.radiance, environment.worldToLocal, environment.scale,
                               Vec3(0.0f), 1.0f, environment.file);
    const double now = map.horizontalIlluminance();
    if (!(now > 0.0)) {
        throw UsageError("--environment-illuminance: " + environment.file +
                         " is black above the horizon; it cannot be scaled to light a plane");
    }
    environment.scale = float(double(environment.scale) * lux / now);
}

void applyEnvironment(const EnvironmentInput& input, SceneDescription& description) {
    const float scale = input.scale.value_or(1.0f);
    const Mat3 turn = environmentRotation(input.rotationDegrees.value_or(0.0f));
    if (input.file && input.sky)
        throw UsageError("--environment and --sky: give one environment light, not both");
    const std::optional<SunPlace> place = placeSun(input);
    const std::optional<SunDisc> sun = makeSun(input, place);
    if (!input.sky && input.skyIlluminance)
        throw UsageError("--sky-illuminance needs --sky");
    if (input.illuminance && (input.scale || input.sky)) {
        throw UsageError(
            "--environment-illuminance sets the scale: not with --environment-scale "
            "or --sky (a sky's is --sky-illuminance)");
    }
    if (!input.sky && !sun && input.groundReflectance)
        throw UsageError("--ground-reflectance needs --sky or --sun-direct-normal");
    if (place && !input.sky && !sun) {
        throw UsageError(
            "--site and --time place the sun for --sky or --sun-direct-normal; "
            "give one of them");
    }
    if (place && input.sky && input.rotationDegrees) {
        throw UsageError(
            "--environment-rotation would turn the sky away from the sun; turn "
            "the site with --north instead");
    }
    if (input.sky || input.file) {
        EnvironmentDesc environment =
            input.sky ? makeSky(input, place, sun) : readEnvironment(*input.file, scale, turn);
        if (input.sky) {
            environment.scale = scale;
            environment.worldToLocal = turn;
        }
        description.environment = std::move(environment);
    } else if (sun && !description.environment) {
        description.environment = makeSunOnly(input, sun);
    } else if (input.scale || input.rotationDegrees) {
        if (!description.environment) {
            throw UsageError(description.file +
                             ": --environment-scale and --environment-rotation need an "
                             "environment: the scene has none; give one with --environment FILE");
        }
        // Turning the map by R about +Y: the map's frame sees world direction d where it saw
        // R^T d.
        description.environment->scale *= scale;
        description.environment->worldToLocal = description.environment->worldToLocal * turn;
    }
    if (input.illuminance)
        scaleToIlluminance(*input.illuminance, description);
    // The sun joins whatever environment there now is: the scene's own, an image or a sky.
    if (sun) {
        description.environment->sun = sun;
        description.environment->file += ", " + place->description;
    }
    const bool none =
        std::find(input.portals.begin(), input.portals.end(), "none") != input.portals.end();
    if (none && input.portals.size() > 1)
        throw UsageError("--portal none: no other --portal may be given with it");
    if (!input.portals.empty() && !none) {
        if (!description.environment) {
            throw UsageError(
                "--portal: the scene has no environment to see through it; give "
                "--sky, --environment or --sun-direct-normal");
        }
        for (const std::string& text : input.portals) {
            if (text != "auto")
                description.environment->portals.push_back(parsePortal(text, description.origin));
        }
    }
}

// The openings detectPortals() finds, for the scene's environment's portals; they are printed in
// --portal's form (the file's frame) unless `quiet`, so that a user can give them again, or edit
// them. Finding none is worth a warning only when the user `asked` for them.
std::vector<Portal> detectedPortals(const Scene& scene, bool asked, bool quiet) {
    const std::vector<Portal> found = detectPortals(scene);
    const SceneDescription& description = scene.description();
    if (found.empty()) {
        if (asked) {
            std::cerr << "penumbra: warning: --portal auto: " << description.file
                      << ": found no opening to the environment (no enclosed interior, or none "
                         "of its rays leaves it); the environment is sampled without portals\n";
        }
        return found;
    }
    if (!quiet) {
        std::cerr << "penumbra: portals: " << found.size() << " opening"
                  << (found.size() > 1 ? "s" : "")
                  << " found, the environment sampled through them (--portal none: not):\n";
        for (const Portal& p : found) {
            const glm::dvec3 o = description.origin, c0 = glm::dvec3(p.corner) + o,
                             c1 = c0 + glm::dvec3(p.edge1), c2 = c0 + glm::dvec3(p.edge2);
            std::cerr << std::setprecision(4) << "  --portal " << c0.x << "," << c0.y << "," << c0.z
                      << "," << c1.x << "," << c1.y << "," << c1.z << "," << c2.x << "," << c2.y
                      << "," << c2.z << "  (" << p.area() << " m²)\n";
        }
    }
    return found;
}

// The luminaire's frame from the script's aim and C0 direction: the nadir (-Z of the frame) along
// the aim, C0 (+X) towards c0 or, by default, towards world +X across the aim (+Z when the aim is
// along X), C90 (+Y) completing a right-handed frame.
Mat3 luminaireFrame(const ScriptLuminaire& luminaire) {
    const glm::dvec3 z =
        -glm::normalize(glm::dvec3(luminaire.aim[0], luminaire.aim[1], luminaire.aim[2]));
    glm::dvec3 c = luminaire.c0
                       ? glm::dvec3((*luminaire.c0)[0], (*luminaire.c0)[1], (*luminaire.c0)[2])
                       : glm::dvec3(1.0, 0.0, 0.0);
    if (!luminaire.c0 && std::abs(z.x) > 0.999)
        c = glm::dvec3(0.0, 0.0, 1.0);
    const glm::dvec3 x = glm::normalize(c - z * glm::dot(z, c));
    return Mat3(glm::dmat3(x, glm::cross(z, x), z));
}

// The most nodes a density grid may have once made dense: 2^28 floats, 1 GiB.
constexpr size_t kMaxDensityNodes = size_t(1) << 28;

// A pass script's [[medium]] table as the scene's medium, its box moved into penumbra's frame.
// A density grid fills the box when one is given, else it stays where its file puts it.
void addMedium(const std::optional<ScriptMedium>& medium, SceneDescription& description) {
    if (!medium)
        return;
    MediumDesc desc;
    desc.name = "[[medium]]";
    desc.sigmaA = Color(medium->sigmaA[0], medium->sigmaA[1], medium->sigmaA[2]);
    desc.sigmaS = Color(medium->sigmaS[0], medium->sigmaS[1], medium->sigmaS[2]);
    desc.g = medium->g;
    desc.emission = Color(medium->emission[0], medium->emission[1], medium->emission[2]);
    if (const auto& box = medium->box) {
        Bounds3 bounds;
        bounds.extend(Vec3(glm::dvec3((*box)[0], (*box)[1], (*box)[2]) - description.origin));
        bounds.extend(Vec3(glm::dvec3((*box)[3], (*box)[4], (*box)[5]) - description.origin));
        desc.box = bounds;
    }
    if (medium->densityFile) {
        VoxelDensity voxels =
            readVdbDensity(*medium->densityFile, medium->densityGrid, kMaxDensityNodes);
        const Vec3 origin(description.origin);
        const Bounds3 box =
            desc.box.value_or(Bounds3{voxels.box.lo - origin, voxels.box.hi - origin});
        desc.density =
            std::make_shared<const DensityGrid>(box, voxels.nodes, std::move(voxels.values));
        desc.box = box;
    }
    description.media.push_back(desc);
}

// A pass script's [[luminaire]] tables as luminaires of the scene, each file read once.
void addLuminaires(const std::vector<ScriptLuminaire>& luminaires, SceneDescription& description) {
    std::map<std::string, std::shared_ptr<const CandelaTable>> tables;
    for (const ScriptLuminaire& luminaire : luminaires) {
        std::shared_ptr<const CandelaTable>& table = tables[luminaire.file];
        if (!table) {
            const std::filesystem::path file(luminaire.file);
            const Photometry photometry = file.extension() == ".ldt" || file.extension() == ".LDT"
                                              ? readLdt(file)
                                              : readIes(file);
            table = std::make_shared<const CandelaTable>(photometry.candela);
        }
        LuminaireDesc desc;
        desc.name = std::filesystem::path(luminaire.file).filename().string();
        desc.table = table;
        desc.position =
            Vec3(glm::dvec3(luminaire.position[0], luminaire.position[1], luminaire.position[2]) -
                 description.origin);
        desc.luminaireToWorld = luminaireFrame(luminaire);
        desc.color = Color(luminaire.color[0], luminaire.color[1], luminaire.color[2]);
        desc.multiplier = luminaire.multiplier;
        description.luminaires.push_back(std::move(desc));
    }
}

}  // namespace

std::unique_ptr<Scene> loadScene(const SceneInput& input) {
    const std::string extension = std::filesystem::path(input.path).extension().string();
    // render, plan and info read a pass script first (readPassScript); the other commands take
    // glTF only.
    if (extension == ".toml") {
        throw UsageError(
            input.path +
            ": pass scripts are for `render`, `plan` and `info`; give a .gltf or .glb");
    }
    if (extension != ".gltf" && extension != ".glb") {
        throw UsageError(input.path + ": unknown scene format '" + extension +
                         "'; expected .gltf or .glb (render, plan and info: or a .toml pass "
                         "script)");
    }
    SceneDescription description = loadGltf(input.path, input.sceneIndex);
    applyEnvironment(input.environment, description);
    addLuminaires(input.luminaires, description);
    addMedium(input.medium, description);
    if (!input.quiet) {
        for (const std::string& warning : description.report.warnings) {
            std::cerr << "penumbra: warning: " << warning << "\n";
        }
    }
    // The openings are found when asked, and by default for a scene with an environment: an
    // interior lit through its windows converges faster with them, and a scene in the open has
    // none to find.
    const auto& portals = input.environment.portals;
    const bool asked = std::find(portals.begin(), portals.end(), "auto") != portals.end();
    Scene::PortalFinder findPortals;
    if (asked || (portals.empty() && description.environment)) {
        findPortals = [asked, quiet = input.quiet](const Scene& scene) {
            return detectedPortals(scene, asked, quiet);
        };
    }
    auto scene = std::make_unique<Scene>(std::move(description), findPortals);
    if (!input.quiet && scene->lights().empty() && !(scene->medium() && scene->medium()->emits())) {
        std::cerr << "penumbra: warning: " << input.path
                  << ": the scene has no lights and no emissive surfaces; the image will be "
                     "black (light it with --environment FILE or --sky MODEL)\n";
    }
    return scene;
}

}  // namespace penumbra::cli
