// Silences OpenMesh's error stream while in scope: add_face() reports a face it refuses
// (non-manifold input) on it, and the callers (radiosity_mesh.cpp, sealed_interiors.cpp) handle
// that case themselves. Internal to the radiosity module, for the files that see OpenMesh.
#pragma once

#include <OpenMesh/Core/System/omstream.hh>

namespace penumbra {

class QuietOpenMeshErrors {
  public:
    QuietOpenMeshErrors() : wasEnabled_(omerr().is_enabled()) { omerr().disable(); }
    ~QuietOpenMeshErrors() {
        if (wasEnabled_)
            omerr().enable();
    }
    QuietOpenMeshErrors(const QuietOpenMeshErrors&) = delete;
    QuietOpenMeshErrors& operator=(const QuietOpenMeshErrors&) = delete;

  private:
    bool wasEnabled_;
};

}  // namespace penumbra
