#pragma once
// fnopt::learned in one include (docs/api.md): every optimizer by name (the registry), the
// learned optimizers and the Fourier neural operator they run, on top of <fnopt/fnopt.hpp>.
#include <fnopt/fnopt.hpp>

#include <fnopt/fno/fno2d.hpp>
#include <fnopt/fno/fno_io.hpp>
#include <fnopt/learned/learned_optimizer.hpp>
#include <fnopt/learned/learned_pqn.hpp>
#include <fnopt/methods/registry.hpp>
