// The torch::fft reference of spectral_conv2d (fno/spectral_conv2d.hpp): the same kept modes
// and normalisation, differentiated by LibTorch.
#include <vector>

#include <fnopt/fno/spectral_conv2d.hpp>
#include <fnopt/fno/spectral_weight.hpp>

namespace fnopt {

torch::Tensor spectral_conv2d_torchfft(const torch::Tensor& x, const torch::Tensor& weight) {
  const fno::KeptModes m = fno::kept_modes_for(x, weight);
  std::vector<int64_t> grid_rows(m.kept_rows);
  for (int64_t k = 0; k < m.kept_rows; ++k) grid_rows[k] = m.grid_row(k);
  const torch::Tensor rows = torch::tensor(grid_rows, torch::dtype(torch::kLong).device(x.device()));

  // norm "forward": rfft2 divides by R·C, irfft2 does not.
  const torch::Tensor x_ft = torch::fft::rfft2(x, c10::nullopt, {-2, -1}, "forward");
  const torch::Tensor x_kept = x_ft.index_select(2, rows).narrow(3, 0, m.kept_cols);
  const torch::Tensor w = torch::view_as_complex(fno::kept_weight(weight, m).contiguous());
  const torch::Tensor y_kept = torch::einsum("bixy,ioxy->boxy", {x_kept, w});
  const torch::Tensor y_ft = torch::constant_pad_nd(
      torch::zeros({x.size(0), weight.size(1), m.rows, m.kept_cols}, y_kept.options()).index_copy(2, rows, y_kept),
      {0, m.half_cols() - m.kept_cols});
  return torch::fft::irfft2(y_ft, torch::IntArrayRef{m.rows, m.cols}, {-2, -1}, "forward");
}

}  // namespace fnopt
