// Light-path components: the image split by what the eye sees first, the way compositors expect
// "light AOVs" (emission, direct, indirect, specular), so that a lighting designer can rebalance
// them and read where the light of a pixel comes from.
//
// In Heckbert's notation (core/light_paths.h), by the vertex next to the eye:
//   emission  L E                  a light seen directly (or through thin glass);
//   direct    L D E                light that reached the first diffuse vertex straight from a
//                                  light (next-event estimation, or a BSDF sample that hit it);
//   indirect  L (D|S)+ D E         light that reached the first diffuse vertex after other
//                                  scattering: interreflection, the radiosity or ambient term,
//                                  caustics seen on a diffuse surface;
//   specular  L (D|S)* S E         everything seen in a mirror or through smooth glass.
// The four sets partition L (D|S)* E (tested with PathSet), so whatever paths a pass counts, its
// component images sum to its image, and over all passes to the beauty.
#pragma once

#include "core/math.h"

#include <array>
#include <string_view>
#include <vector>

namespace penumbra {

enum class PathComponent { Emission, Direct, Indirect, Specular };

inline constexpr size_t kPathComponentCount = 4;
inline constexpr std::array<std::string_view, kPathComponentCount> kPathComponentNames = {
    "emission", "direct", "indirect", "specular"};
// The Heckbert expression of each component, in the order of the enum.
inline constexpr std::array<std::string_view, kPathComponentCount> kPathComponentPaths = {
    "L E", "L D E", "L (D|S)+ D E", "L (D|S)* S E"};

inline std::string_view componentName(PathComponent c) {
    return kPathComponentNames[static_cast<size_t>(c)];
}

// The component of a path by the vertices it scatters at: none is emission; a path whose first
// vertex from the eye is specular is specular whatever follows; else direct with one vertex and
// indirect with more.
inline PathComponent pathComponent(int vertices, bool firstVertexSpecular) {
    if (vertices == 0)
        return PathComponent::Emission;
    if (firstVertexSpecular)
        return PathComponent::Specular;
    return vertices == 1 ? PathComponent::Direct : PathComponent::Indirect;
}

// Radiance (cd/m², per channel) split into the components; total() is the radiance itself.
struct PathRadiance {
    std::array<Color, kPathComponentCount> components{Color(0.0f), Color(0.0f), Color(0.0f),
                                                      Color(0.0f)};
    // The part of each component that corrects a reused radiosity solution's bias (the
    // hybrid's correction, raytrace/path_tracer.h) and that the image is to reconstruct on its
    // own, counted in `components` as well: zero for every other estimator. The image renderer
    // keeps its mean apart for its filter (raytrace/correction_filter.h), whose width each pixel
    // chooses: narrow where the correction is sharp, as where a glossy floor reflects it.
    std::array<Color, kPathComponentCount> corrections{Color(0.0f), Color(0.0f), Color(0.0f),
                                                       Color(0.0f)};

    // The radiance by light group (core/light_groups.h), for an estimator asked to file it so
    // (one entry per group, summing to total()); empty otherwise.
    std::vector<Color> groups;

    Color& operator[](PathComponent c) { return components[static_cast<size_t>(c)]; }
    const Color& operator[](PathComponent c) const { return components[static_cast<size_t>(c)]; }

    Color total() const { return components[0] + components[1] + components[2] + components[3]; }
    Color correction() const {
        return corrections[0] + corrections[1] + corrections[2] + corrections[3];
    }

    PathRadiance& operator*=(const Color& weight) {
        for (Color& c : components)
            c *= weight;
        for (Color& c : corrections)
            c *= weight;
        for (Color& c : groups)
            c *= weight;
        return *this;
    }
};

}  // namespace penumbra
