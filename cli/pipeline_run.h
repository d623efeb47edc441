// Running a pipeline over a loaded scene: the part of a render that `penumbra render` and
// `penumbra bench` share (loading is cli/scene_input.h, writing is core/image_io.h).
#pragma once

#include "core/camera.h"
#include "core/image.h"
#include "core/image_io.h"
#include "core/render_settings.h"
#include "core/scene.h"
#include "core/scene_contents.h"
#include "passes/pipeline.h"

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace penumbra::cli {

struct PipelineRun {
    std::map<std::string, Image> layers;     // "beauty" and the AOVs; empty when stopped
    std::vector<std::string> contributions;  // the layers that sum to the beauty
    std::vector<std::string> lightGroups;    // "light.GROUP" layers, which sum to it too
    double seconds = 0.0;                    // wall-clock time of every pass's prepare and run
    bool stopped = false;                    // `stop` ended the run before its image was formed
};

// Prepares and runs every pass of `pipeline` in order, over `scene` (whose analysis is
// `contents`, the one the pipeline was planned with) seen by `camera` with
// `settings` (width and height resolved), on settings.threads worker threads (0: all cores).
//
// settings.timeLimit (seconds, 0 = none) holds the pipeline as a whole, as Pipeline::run says.
// `stop`, when given, is asked after every step; if it answers true the run is abandoned:
// stopped = true and no layers.
PipelineRun runPipeline(Pipeline& pipeline, const Scene& scene, const SceneContents& contents,
                        const Camera& camera, const RenderSettings& settings,
                        const std::function<bool()>& stop = {});

// The metadata every rendered image carries: penumbra version, pipeline, seed, `seconds`, scene
// file, camera name, filter, then each pass's stats as "penumbra:<pass type>.<key>" and
// "penumbra:spp" (the samples per pixel reached) from the pass that reports them.
ImageMetadata renderMetadata(const Pipeline& pipeline, const RenderSettings& settings,
                             double seconds, const std::string& scenePath,
                             const std::string& cameraName);

// The value of the stat `key` from the last pass that reports it; empty if none does.
std::string passStat(const Pipeline& pipeline, const std::string& key);

}  // namespace penumbra::cli
