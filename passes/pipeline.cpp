#include "passes/pipeline.h"

#include "core/stats.h"
#include "passes/composite.h"

#include <chrono>

namespace penumbra {

bool Pipeline::run(PassContext& context, const StepHook& hook) {
    for (size_t i = 0; i < passes_.size(); ++i) {
        if (skipped_[i])
            continue;
        if (hook && !hook(0.0))
            return false;
        passes_[i]->prepare(context);
        for (;;) {
            const auto stepStart = std::chrono::steady_clock::now();
            if (passes_[i]->run(context))
                break;
            if (hook && !hook(secondsSince(stepStart)))
                return false;
        }
    }
    if (context.layers.count("beauty") == 0)
        compositeContributions(context);
    return true;
}

}  // namespace penumbra
