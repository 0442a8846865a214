#include <fnopt/fno/spectral_weight.hpp>

#include <sstream>

#include <fnopt/util/error.hpp>

namespace fnopt::fno {

KeptModes kept_modes_for(const torch::Tensor& x, const torch::Tensor& weight) {
  const auto shapes = [&] {
    std::ostringstream s;
    s << "input " << x.sizes() << ", weight " << weight.sizes();
    return s.str();
  };
  require(x.dim() == 4, "spectral convolution", "input must be [B, in, R, C], got " + shapes());
  require(weight.dim() == 5 && weight.size(4) == 2 && weight.size(3) >= 1, "spectral convolution",
          "weight must be [in, out, modes_x, modes_y/2 + 1, 2], got " + shapes());
  require(weight.size(0) == x.size(1), "spectral convolution",
          "input channels differ from the weight's, got " + shapes());
  require(x.scalar_type() == weight.scalar_type(), "spectral convolution", "input and weight must have one dtype");
  return kept_modes(x.size(2), x.size(3), weight.size(2), 2 * (weight.size(3) - 1));
}

torch::Tensor kept_weight(const torch::Tensor& weight, const KeptModes& modes) {
  if (modes.kept_rows == weight.size(2) && modes.kept_cols == weight.size(3)) return weight;
  return weight.narrow(2, modes.weight_row_offset, modes.kept_rows).narrow(3, 0, modes.kept_cols);
}

}  // namespace fnopt::fno
