#include "passes/pipeline.h"

namespace penumbra {

void Pipeline::run(PassContext& context) {
    for (const auto& pass : passes_) {
        pass->prepare(context);
        while (!pass->run(context)) {
        }
    }
}

}  // namespace penumbra
