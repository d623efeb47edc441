// The names of the products passes hand to later passes (PassContext::publish and product(),
// Pass::products() and needs()), in one place: a pass that makes or reads a product names it by
// its constant here, never by a string of its own.
#pragma once

#include <string>

namespace penumbra::products {

// The radiosity solution (a RadiositySolution, radiosity/radiosity_solution.h), made by a pass of
// type "radiosity".
inline const std::string kRadiositySolution = "radiosity";
// The caustic photon map (a CausticMap, caustics/caustic_map.h), made by a pass of type
// "caustics" with method "photon_map".
inline const std::string kCausticMap = "caustic map";

// The pass type a script adds to make `product`, for messages.
inline std::string passTypeMaking(const std::string& product) {
    return product == kCausticMap ? "caustics" : product;
}

}  // namespace penumbra::products
