#pragma once
// Between the solver's stacked vectors (vertex k = i*C + j at [3k, 3k+3)) and the FNO's
// per-coordinate samples [3, 1, R, C] (sample c holds coordinate c of every vertex).
#include <torch/torch.h>

#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/cloth/grid.hpp>

namespace fnopt {

// factor * v as float samples [3, 1, R, C].
torch::Tensor to_coordinate_samples(const VecX& v, const Grid& grid, double factor = 1.0);
// v += factor * samples, samples [3, 1, R, C].
void add_coordinate_samples(const torch::Tensor& samples, const Grid& grid, double factor, VecX& v);
// [1, 1, R, C]: 1 at free vertices, 0 at handles.
torch::Tensor free_mask(const DirichletSet& dirichlet, const Grid& grid);

}  // namespace fnopt
