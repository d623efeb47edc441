// Writing glTF 2.0 files of unlit, vertex-coloured triangle meshes: the export side of glTF, as
// core/gltf_loader.h is the import side. It knows nothing of how the colours were computed (the
// radiosity bake, radiosity/bake.h, is its first user); tinygltf does the serialisation and is
// seen by gltf_writer.cpp only.
#pragma once

#include "core/math.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace penumbra {

// An application-specific vertex attribute (glTF 2.0, section 3.7.2.1): a name starting with an
// underscore, e.g. "_RADIANCE", and `components` (1 to 4) floats per vertex, written as a FLOAT
// SCALAR, VEC2, VEC3 or VEC4 accessor. Viewers ignore it; tools such as Blender's importer keep it.
struct GltfAttribute {
    std::string name;
    int components = 1;
    std::vector<float> values;
};

// One triangle mesh, written as one glTF mesh with one primitive (mode TRIANGLES) and one node.
struct GltfMeshData {
    std::string name;
    // Positions in metres, relative to GltfModelData::origin; normals unit length, or empty to
    // write none. Both in the glTF frame (+Y up, right-handed), as the scene that was read.
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;
    // Linear (not sRGB-encoded) colours in [0, 1], colorComponents (3: RGB or 4: RGBA) floats per
    // vertex, written as the FLOAT COLOR_0 attribute; empty to write none. glTF viewers multiply
    // them by the material's base colour (white here). The range is the specification's: the
    // Khronos glTF-Validator reports a float COLOR_0 outside [0, 1] as an error
    // (ACCESSOR_NON_CLAMPED), so values beyond it belong in a custom attribute.
    std::vector<float> colors;
    int colorComponents = 3;
    std::vector<GltfAttribute> customAttributes;
    // Three vertex indices per triangle, counter-clockwise seen from the front.
    std::vector<uint32_t> indices;
    // Meshes with the same material name and doubleSided flag share one glTF material: white,
    // unlit (KHR_materials_unlit), with the extension's recommended fallback for viewers that
    // lack it (metallic 0, roughness 0.9).
    std::string material;
    bool doubleSided = false;
};

struct GltfModelData {
    // Where the meshes' positions are relative to, in the file's frame (metres). Written as the
    // translation of the root node holding every mesh node, in double precision, so that a model
    // far from the file's origin keeps the precision its float positions have near their origin.
    glm::dvec3 origin{0.0};
    std::vector<GltfMeshData> meshes;
    std::string generator;  // asset.generator, e.g. "penumbra 0.1.0"
};

// Throws UsageError("<path>: ...") unless `path` ends in .glb or .gltf (case-insensitive) and its
// directory exists. The command line calls it before hours of work, writeGltf() again.
void checkGltfOutputPath(const std::string& path);

// Writes the model to `path`: a binary .glb (one BIN chunk), or a .gltf with the buffer embedded
// as a base64 data URI, so that either way one self-contained file is written. Every buffer view
// starts on a 4-byte boundary; POSITION accessors carry min and max (glTF 2.0, section 5.1.1).
// The file is first written to "<stem>.tmp-<pid><ext>" in the same directory and renamed over
// `path` only when complete; on any failure the temporary is removed and `path` is left as it
// was. Throws UsageError for a bad path or a failed write, std::invalid_argument for inconsistent
// data (a size that is not a multiple of the components, an index out of range, a non-finite
// value, a colour outside [0, 1], a custom attribute name without the leading underscore or used
// twice). Returns the size of the file written, in bytes.
size_t writeGltf(const std::string& path, const GltfModelData& model);

}  // namespace penumbra
