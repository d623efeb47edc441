// What a scene holds that decides which passes it needs and which light paths it can have:
// analysed once per render (the planner skips passes by it, PassContext carries it to the passes).
#pragma once

#include "core/scene.h"

#include <cstddef>

namespace penumbra {

struct SceneContents {
    bool diffuse = false;   // a surface with a diffuse or rough glossy lobe (D vertices)
    bool specular = false;  // a surface with a specular (delta) lobe (S vertices)
    size_t areaLights = 0, punctualLights = 0;
    bool environment = false;  // an environment light (Scene::environment())
    // A participating medium (Scene::medium()), whether it scatters (V vertices) and whether it
    // emits (a source of light too).
    bool medium = false;
    bool mediumScatters = false;
    bool mediumEmits = false;
    // How large the lights look from the specular meshes (steradians): the solid angle of all
    // the area lights summed, seen from the centre of each mesh with a specular lobe, averaged
    // over those meshes weighted by the light power that can reach each (each light's power
    // times the fraction of its sky the mesh's bounding sphere covers, as its caustic photons
    // are aimed). A path tracer finds the caustic of a light through a specular surface with a
    // probability of about this solid angle over pi (a diffuse bounce towards the surface, then
    // the light behind it); a photon map is for lights that look small, whose caustics paths
    // from the eye seldom find (Jensen 1996, "Global Illumination using Photon Maps"). 0 without
    // specular meshes or area lights.
    float lightSolidAngleAtSpecular = 0.0f;
    // A surface with a sharp glossy lobe (Bsdf::hasSharpGlossyLobe: D vertices that a radiosity
    // solution can carry as S ones, passes/specular_transfer.h).
    bool sharpGlossy = false;
};

// A sphere around a mesh: centred on its bounding box, through its farthest vertex.
struct Sphere {
    Vec3 center;
    float radius;
};
Sphere boundingSphere(const Mesh& mesh);

// Classifies each mesh's material at up to 16 of its triangles (enough to meet the rough and
// smooth parts of a textured roughness, few enough for scenes of millions of triangles) and
// counts the lights.
SceneContents analyseScene(const Scene& scene);

}  // namespace penumbra
