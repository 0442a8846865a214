#pragma once
// Weight-space interpolation of two FNOs of one shape: (1 - t) a + t b, parameter by parameter.
// Why: a model trained on from another stays connected to it by a path of models along which the
// errors trade smoothly (Wortsman et al. 2022, "Robust fine-tuning of zero-shot models": WiSE-FT), so
// a blend of the 32^2 model and its continuation on finer grids can hold both (docs/training.md,
// "Blending two models").
#include <fnopt/fno/fno2d.hpp>

namespace fnopt {

// The blend, a new model with a's options. Throws Error("blend", ...) for t outside [0, 1] or models
// whose architectures differ (the option that differs is named).
FNO2d blend_fno(const FNO2d& a, const FNO2d& b, double t);

}  // namespace fnopt
