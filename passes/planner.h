// Planning a pipeline: the passes are fitted to each other (Pass::adapt), their light-path
// declarations are checked so that every path is counted at most once (a script that counts a
// path twice is refused, naming a shortest such path), the scene is analysed to skip what it
// does not need, and the paths no pass counts are named as warnings. `penumbra plan` prints the
// result; `penumbra render` logs it. The partition of every built-in pipeline is in
// docs/light-paths.md.
#pragma once

#include "core/scene_contents.h"
#include "passes/pipeline.h"

#include <optional>
#include <string>
#include <vector>

namespace penumbra {

// What is wrong with a pipeline, and the pass (0-based) where it shows: the caller throws the
// error (a script's at the pass's table, a preset's naming the pipeline).
struct PipelineProblem {
    size_t pass = 0;
    std::string message;
};

// Scene-independent checks, run when a pipeline is built: every pass gets adapt() with the shape
// of the rest of the pipeline; then the first problem is returned: a product needed before any
// pass makes it, or two passes whose images hold a common light path.
std::optional<PipelineProblem> checkPipeline(Pipeline& pipeline);

struct PipelinePlan {
    std::string universe;  // the light paths the scene can hold, e.g. "L(D|S)*E"
    // One line per decision, with its reason ("caustics: skipped: no specular surface").
    std::vector<std::string> decisions;
    // Light paths of the universe no pass counts, each named by its shortest instances.
    std::vector<std::string> warnings;
};

// The scene-dependent part: marks passes the scene does not need as skipped in the pipeline, and
// finds the light paths the remaining passes leave out.
PipelinePlan planForScene(Pipeline& pipeline, const SceneContents& contents);

}  // namespace penumbra
