#include <fnopt/fno/pointwise_linear.hpp>

namespace fnopt::fno {

torch::Tensor pointwise_linear(const torch::Tensor& x, const torch::nn::Linear& linear) {
  const int64_t batch = x.size(0), rows = x.size(2), cols = x.size(3);
  const torch::Tensor& w = linear->weight;
  const torch::Tensor x3 = x.reshape({batch, x.size(1), rows * cols});
  return torch::baddbmm(linear->bias.view({1, -1, 1}), w.expand({batch, -1, -1}), x3)
      .view({batch, w.size(0), rows, cols});
}

}  // namespace fnopt::fno
