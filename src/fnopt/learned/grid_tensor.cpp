#include <fnopt/learned/grid_tensor.hpp>

namespace fnopt {

torch::Tensor to_coordinate_samples(const VecX& v, const Grid& grid, double factor) {
  const auto stacked = torch::from_blob(const_cast<double*>(v.data()), {grid.rows, grid.cols, 3}, torch::kFloat64);
  return (stacked.permute({2, 0, 1}) * factor).to(torch::kFloat32).unsqueeze(1).contiguous();
}

void add_coordinate_samples(const torch::Tensor& samples, const Grid& grid, double factor, VecX& v) {
  const auto stacked = samples.detach().squeeze(1).permute({1, 2, 0}).to(torch::kFloat64).contiguous();
  v += factor * Eigen::Map<const VecX>(stacked.data_ptr<double>(), grid.dof_count());
}

torch::Tensor free_mask(const DirichletSet& dirichlet, const Grid& grid) {
  auto mask = torch::ones({1, 1, grid.rows, grid.cols});
  auto flat = mask.view({-1});
  for (int k : dirichlet.fixed_vertices()) flat[k] = 0.0;
  return mask;
}

}  // namespace fnopt
