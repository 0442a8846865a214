#pragma once
// A linear map over the channel axis applied at every grid point (a 1×1 convolution), on the
// [B, channels, R, C] layout the spectral convolution needs, as one batched GEMM W·X over the
// [B, channels, R·C] view. With OpenBLAS it is at least as fast as torch::conv2d (1×1) and
// torch::nn::Linear on a channels-last permute, and needs no layout change.
#include <torch/torch.h>

namespace fnopt::fno {

// y[b, :, r, c] = W · x[b, :, r, c] + bias, with W and bias from `linear` ([out, in], [out]).
torch::Tensor pointwise_linear(const torch::Tensor& x, const torch::nn::Linear& linear);

}  // namespace fnopt::fno
