// Writes small glTF 2.0 test scenes (one self-contained .gltf with a data-URI buffer), so that
// analytic end-to-end tests own their scenes in code instead of in binary files.
#pragma once

#include "core/math.h"

#include <string>
#include <vector>

namespace penumbra::test {

struct TestMaterial {
    Color baseColor{0.8f};
    Color emissive{0.0f};  // emissiveFactor (each component <= 1)
    float emissiveStrength = 1.0f;
    bool lambertian = true;  // KHR_materials_specular specularFactor 0
    bool doubleSided = false;
    float metallic = 0.0f;
    float roughness = 1.0f;
    std::string name{};  // written when not empty
};

struct TestLight {
    std::string type = "point";  // point, spot, directional
    std::string name{};          // written when not empty
    Color color{1.0f};
    float intensity = 1.0f;
    Vec3 position{0.0f};
    // glTF rotation quaternion (x, y, z, w) of the light's node; lights shine down their -Z
    Vec4 rotation{0.0f, 0.0f, 0.0f, 1.0f};
    float innerConeAngle = 0.0f, outerConeAngle = kPi / 4.0f;
};

// A measured luminaire (EXT_lights_ies): a profile file and the node that places it.
struct TestLuminaire {
    std::string uri;  // the IES or LDT file, relative to the glTF file
    Vec3 position{0.0f};
    // glTF rotation quaternion (x, y, z, w) of the node; the profile's nadir is the node's -Z
    Vec4 rotation{0.0f, 0.0f, 0.0f, 1.0f};
    float multiplier = 1.0f;
    Color color{1.0f};
};

class GltfBuilder {
  public:
    int addMaterial(const TestMaterial& material);
    // A triangle mesh in world space (its node has no transform), counter-clockwise = front.
    void addMesh(const std::vector<Vec3>& positions, const std::vector<uint32_t>& indices,
                 int material);
    // A quad p0 p1 p2 p3 (counter-clockwise seen from its front side).
    void addQuad(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3, int material);
    void addLight(const TestLight& light);
    // One profile per luminaire in the extension's `lights`, one node each.
    void addLuminaire(const TestLuminaire& luminaire) { luminaires_.push_back(luminaire); }
    // An orthographic camera at `position` looking along -Z rotated by `rotation` (x, y, z, w).
    void setOrthographicCamera(const Vec3& position, const Vec4& rotation, float xmag, float ymag);
    void setPerspectiveCamera(const Vec3& position, const Vec4& rotation, float yfov);
    // Translation and uniform scale of a root node that holds everything (for robustness tests).
    void setRootTransform(const Vec3& translation, float scale);

    // The scene's `extras` object, as JSON text (e.g. an environment record).
    void setSceneExtras(const std::string& json) { sceneExtras_ = json; }

    std::string json() const;
    void write(const std::string& path) const;

  private:
    struct MeshData {
        std::vector<Vec3> positions;
        std::vector<uint32_t> indices;
        int material;
    };
    std::vector<TestMaterial> materials_;
    std::vector<MeshData> meshes_;
    std::vector<TestLight> lights_;
    std::vector<TestLuminaire> luminaires_;
    std::string cameraJson_;
    std::string sceneExtras_;
    Vec3 cameraPosition_{0.0f};
    Vec4 cameraRotation_{0.0f, 0.0f, 0.0f, 1.0f};
    Vec3 rootTranslation_{0.0f};
    float rootScale_ = 1.0f;
};

}  // namespace penumbra::test
