#include "core/batch_math.h"

#include <cmath>

#if defined(__x86_64__)
#include <emmintrin.h>
#include <sleef.h>
#endif

namespace penumbra {

Atan2Batch atan2Batch(const Atan2Batch& y, const Atan2Batch& x) {
    Atan2Batch out;
#if defined(__x86_64__)
    // SSE2 is part of x86-64, so the two-lane functions need no dispatch.
    static_assert(kAtan2BatchSize % 2 == 0);
    for (size_t i = 0; i < kAtan2BatchSize; i += 2)
        _mm_storeu_pd(&out[i], Sleef_atan2d2_u35(_mm_loadu_pd(&y[i]), _mm_loadu_pd(&x[i])));
#else
    for (size_t i = 0; i < kAtan2BatchSize; ++i)
        out[i] = std::atan2(y[i], x[i]);
#endif
    return out;
}

}  // namespace penumbra
