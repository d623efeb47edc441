// Time limits as the passes and the radiosity solver keep them: a point on the steady clock by
// which work is to end, or none.
#pragma once

#include <chrono>
#include <optional>

namespace penumbra {

using Deadline = std::optional<std::chrono::steady_clock::time_point>;

// Whether `deadline` has come (never without one).
inline bool deadlinePassed(const Deadline& deadline) {
    return deadline && std::chrono::steady_clock::now() >= *deadline;
}

// Whether a step begun now would end past `deadline` (never without one), the step taken to last
// `lastStep`, as long as the one before it: the rule by which work done in steps (the pipeline's
// passes of samples, the solve's refinement rounds, the final gather's passes, the specular
// transfer's rounds) ends before a step it has no time for, instead of after it.
inline bool nextStepWouldOverrun(std::chrono::steady_clock::duration lastStep,
                                 const Deadline& deadline) {
    return deadline && std::chrono::steady_clock::now() + lastStep > *deadline;
}

}  // namespace penumbra
