#include "cli/pipeline_run.h"

#include "core/stats.h"
#include "core/version.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>

namespace penumbra::cli {

PipelineRun runPipeline(Pipeline& pipeline, const Scene& scene, const SceneContents& contents,
                        const Camera& camera, const RenderSettings& settings,
                        const std::function<bool()>& stop) {
    const int threads = settings.threads > 0 ? settings.threads : tbb::info::default_concurrency();
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads);
    PassContext context(scene, contents, camera, settings);
    PipelineRun result;
    const auto start = std::chrono::steady_clock::now();
    result.stopped = !pipeline.run(context, stop);
    result.seconds = secondsSince(start);
    if (result.stopped)
        return result;
    result.layers = std::move(context.layers);
    result.contributions = std::move(context.contributions);
    return result;
}

ImageMetadata renderMetadata(const Pipeline& pipeline, const RenderSettings& settings,
                             double seconds, const std::string& scenePath,
                             const std::string& cameraName) {
    ImageMetadata metadata;
    metadata.set("penumbra:version", std::string(kVersion));
    metadata.set("penumbra:pipeline", pipeline.name());
    metadata.set("penumbra:seed", static_cast<int>(settings.seed));
    metadata.set("penumbra:seconds", static_cast<float>(seconds));
    metadata.set("penumbra:scene", scenePath);
    metadata.set("penumbra:camera", cameraName);
    metadata.set("penumbra:filter", settings.filter);
    for (size_t i = 0; i < pipeline.passes().size(); ++i) {
        const Pass& pass = *pipeline.passes()[i];
        if (pipeline.skipped(i)) {
            metadata.set("penumbra:" + pass.type() + ".skipped", std::string("true"));
            continue;
        }
        for (const auto& [key, value] : pass.stats()) {
            metadata.set("penumbra:" + pass.type() + "." + key, value);
            if (key == "spp")
                metadata.set("penumbra:spp", std::stoi(value));
        }
    }
    return metadata;
}

std::string passStat(const Pipeline& pipeline, const std::string& key) {
    std::string found;
    for (size_t i = 0; i < pipeline.passes().size(); ++i) {
        if (pipeline.skipped(i))
            continue;
        for (const auto& [name, value] : pipeline.passes()[i]->stats()) {
            if (name == key)
                found = value;
        }
    }
    return found;
}

}  // namespace penumbra::cli
