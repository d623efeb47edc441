// The first stage of scene loading: everything read from a glTF file, validated, flattened to
// world space, and still remembering where each thing came from. `Scene` (scene.h) is built from
// it and adds the acceleration structure and the light list.
#pragma once

#include "core/image.h"
#include "core/material.h"
#include "core/math.h"
#include "core/medium.h"
#include "core/photometry.h"
#include "core/portals.h"
#include "core/sun_disc.h"
#include "core/texture.h"

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace penumbra {

// One glTF primitive instanced by one node, in world space.
struct Mesh {
    std::string name;    // "<mesh name or index>/<primitive index>" for messages and reports
    std::string source;  // JSON pointer of the primitive, e.g. "/meshes/3/primitives/0"
    int material = -1;   // index into SceneDescription::materials (the default material if absent)

    std::vector<Vec3> positions;           // world space, metres
    std::vector<Vec3> normals;             // world space, unit; empty = use the geometric normal
    std::vector<Vec4> tangents;            // world space xyz + handedness w; empty when not needed
    std::array<std::vector<Vec2>, 2> uvs;  // TEXCOORD_0 and TEXCOORD_1 (may be empty)
    // Vertex indices, counter-clockwise = front face. Winding is already flipped for
    // negative-determinant node transforms; degenerate triangles are already dropped.
    std::vector<glm::uvec3> triangles;
};

enum class PunctualType { Point, Spot, Directional };

// KHR_lights_punctual light placed by a node, in world space.
struct PunctualLightDesc {
    std::string name;
    PunctualType type = PunctualType::Point;
    Color color{1.0f};
    float intensity = 1.0f;  // candela (point, spot) or lux (directional)
    float range = 0.0f;      // 0 = infinite
    float innerConeAngle = 0.0f;
    float outerConeAngle = kPi / 4.0f;
    Vec3 position{0.0f};
    Vec3 direction{0.0f, 0.0f, -1.0f};  // direction the light travels (node's -Z), unit
};

// A measured luminaire (glTF EXT_lights_ies): a goniometric point light
// (core/goniometric_light.h) whose table the luminaires of one profile share.
struct LuminaireDesc {
    std::string name;  // the profile's name or file, for messages
    std::shared_ptr<const CandelaTable> table;
    Vec3 position{0.0f};
    Mat3 luminaireToWorld{1.0f};  // a rotation: the nadir along this frame's -Z, C0 along +X
    Color color{1.0f};            // linear, in [0, 1]
    float multiplier = 1.0f;      // >= 0
};

enum class ProjectionType { Perspective, Orthographic };

struct CameraDesc {
    std::string name;
    ProjectionType projection = ProjectionType::Perspective;
    float yfov = 0.8f;               // radians (perspective)
    float aspectRatio = 0.0f;        // 0 = not given
    float xmag = 1.0f, ymag = 1.0f;  // half extents (orthographic)
    float znear = 0.01f;
    Mat4 cameraToWorld{1.0f};  // rigid: the camera looks down its -Z, +Y up
};

// An environment light's source (core/environment_light.h): an equirectangular image of the
// radiance arriving from every direction, read and checked (every value finite and >= 0).
struct EnvironmentDesc {
    std::string file;             // as given, for messages
    Image radiance;               // times `scale`: cd/m² per linear-sRGB channel
    float scale = 1.0f;           // > 0
    Mat3 worldToLocal{1.0f};      // rotation from world directions into the map's frame
    std::optional<SunDisc> sun;   // the sun's disc, in world directions (not turned by the map's)
    std::vector<Portal> portals;  // the openings it is seen through (core/portals.h), rebased
};

// What the loader noticed, for `penumbra info` and warnings.
struct LoadReport {
    std::vector<std::string> extensionsUsed;     // supported and used
    std::vector<std::string> extensionsIgnored;  // used by the file, not supported (not required)
    size_t degenerateTriangles = 0;              // dropped
    std::vector<std::string> warnings;
};

struct SceneDescription {
    std::string file;  // path as given
    // Where penumbra's world origin lies in the file's coordinates (metres). Everything is
    // stored relative to it (rebased on the centre of the geometry, so that a model placed far
    // from the file's origin keeps its precision in float).
    glm::dvec3 origin{0.0};
    std::vector<Mesh> meshes;
    std::vector<Material> materials;  // last entry is the glTF default material when used
    std::vector<Texture> textures;
    std::vector<PunctualLightDesc> lights;
    std::vector<LuminaireDesc> luminaires;
    std::vector<CameraDesc> cameras;
    // From the scene's `extras` (a converted Mitsuba scene's envmap), or given by the user.
    std::optional<EnvironmentDesc> environment;
    // Participating media (core/medium.h), given by a pass script; at most one for now.
    std::vector<MediumDesc> media;
    std::string sceneExtrasJson;  // the loaded scene's `extras` as JSON text (e.g. a sky), or empty
    LoadReport report;
};

}  // namespace penumbra
