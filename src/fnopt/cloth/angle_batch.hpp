#pragma once
// The angle springs of AngleKernel (angle_kernel.hpp), evaluated a batch of stencils at a time on
// SIMD lanes: one stencil a lane, AVX2's 4 or AVX-512's 8; energy, gradient and the unprojected
// Hessian (the projected one stays per stencil). Each batch reads its vertices through its
// stencils' coordinate offsets, stored batch by batch as 3 rows of `width` ints (vertex i of lane l
// at offsets[i * width + l], 3 times the vertex index), and writes structure of arrays:
//   gradients: per batch 10 rows of `width`: rows 3i + c the gradient's coordinate c at vertex i,
//              row 9 the energy;
//   energies:  per batch 1 row of `width`;
//   hessians:  per batch 81 rows of `width`: row 9c + r the unprojected Hessian's entry (r, c).
// The lanes repeat the scalar kernel's operations in its order and rounding (no contraction into
// fused multiply-adds), with the lanes' atan2 (util/simd_atan2.hpp) for std::atan2: a batch's
// results are the scalar kernel's up to atan2's last bits (tests/cloth/test_angle_batch.cpp).
// Only the two layouts whose edges are vertex differences are batched: Corner (shear) and Hinge
// (bend).
#include <fnopt/util/simd_level.hpp>

namespace fnopt {

struct AngleBatchParams {
  double stiffness = 0.0;   // K
  double rest_angle = 0.0;  // theta0 [rad]; 0 selects the series near theta = 0, as in AngleKernel
  bool corner = true;       // Corner: u = x1 - x0, w = x2 - x0; else Hinge: u = x1 - x0, w = x2 - x1
};

using AngleBatchFunction = void (*)(const AngleBatchParams& params, const double* x, const int* offsets, long batches,
                                    double* out);

// The widest batch: AVX-512's 8 doubles.
constexpr int kAngleBatchMaxWidth = 8;

struct AngleBatchKernels {
  int width = 0;                           // stencils a batch
  AngleBatchFunction gradients = nullptr;  // energy and gradient of `batches` consecutive batches
  AngleBatchFunction energies = nullptr;   // energy alone
  AngleBatchFunction hessians = nullptr;   // the Hessian, unprojected
};

// The kernels for Avx2 or Avx512, which the CPU must support (simd_level_supported).
AngleBatchKernels angle_batch_kernels(SimdLevel level);

}  // namespace fnopt
