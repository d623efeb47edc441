#include "passes/pipeline.h"

#include "passes/composite.h"

#include <chrono>

namespace penumbra {

bool Pipeline::run(PassContext& context, const std::function<bool()>& abandon) {
    using Clock = std::chrono::steady_clock;
    const double limit = context.settings.timeLimit;
    if (limit > 0.0) {
        context.deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                              std::chrono::duration<double>(limit));
    }
    for (size_t i = 0; i < passes_.size(); ++i) {
        if (skipped_[i])
            continue;
        if (abandon && abandon())
            return false;
        Pass& pass = *passes_[i];
        pass.prepare(context);
        for (;;) {
            const Clock::time_point stepStart = Clock::now();
            if (pass.run(context))
                break;
            if (abandon && abandon())
                return false;
            // Without a time limit the publishing time is not asked (the hybrid would time its
            // reconstruction's cost for nothing).
            if (context.deadline &&
                nextStepWouldOverrun(Clock::now() - stepStart + pass.publishingTime(),
                                     context.deadline) &&
                pass.stopEarly(context)) {
                break;
            }
        }
    }
    if (context.layers.count("beauty") == 0)
        compositeContributions(context);
    return true;
}

}  // namespace penumbra
