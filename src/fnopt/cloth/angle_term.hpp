#pragma once
// The angle springs' term (shear or bend, angle_kernel.hpp): energy, gradient and the unprojected
// Hessian a batch of stencils at a time on the CPU's widest SIMD lanes (angle_batch.hpp), the
// projected Hessian per stencil through StencilTerm<AngleKernel> (stencil_term.hpp), which is also
// the whole term at SimdLevel::Scalar and for the General layout. The batches cover the stencils' largest multiple
// of the lane count; the rest go through the scalar kernel. Sums run in stencil order, as in
// StencilTerm: on one thread each chunk of batches is added right after it is evaluated, on several
// the batches are evaluated in parallel into one buffer and added serially. Not safe to evaluate
// from two threads.
#include <array>
#include <string>
#include <vector>

#include <fnopt/cloth/angle_batch.hpp>
#include <fnopt/cloth/angle_kernel.hpp>
#include <fnopt/cloth/stencil_term.hpp>

namespace fnopt {

class AngleTerm final : public EnergyTerm {
 public:
  using Stencil = std::array<int, 3>;

  // `level` must be supported by the CPU (simd_level_supported).
  AngleTerm(std::string name, AngleKernel kernel, std::vector<Stencil> stencils, SimdLevel level = best_simd_level());

  const std::string& name() const override { return scalar_.name(); }
  SimdLevel simd_level() const { return level_; }

  double energy(const VecX& x) const override;
  double accumulate_gradient(const VecX& x, VecX& grad) const override;
  int register_hessian(HessianAssembly& assembly) const override { return scalar_.register_hessian(assembly); }
  void accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const override;
  // The exact Hessian from the batches, as accumulate_hessian(x, false, ...) adds it (bit for bit), and
  // the projected one per stencil, as accumulate_hessian(x, true, ...) adds it.
  void accumulate_hessian_pair(const VecX& x, HessianAssembly& assembly, int handle) const override;

 private:
  // Batches evaluated per call of a batch kernel, and added together on one thread.
  static constexpr long kChunk = 16;

  long batches() const { return static_cast<long>(offsets_.size()) / (3 * kernels_.width); }
  // Adds batches [first, first + count)'s gradients in `out` (angle_batch.hpp's layout) to grad,
  // stencil by stencil; returns their energies' sum.
  double add_batches(long first, long count, const double* out, VecX& grad) const;

  // Whether StencilTerm runs serially: below its threshold or on one thread.
  bool serial() const;
  // Evaluates batches [0, batches()) with `kernel` into chunks of `rows` rows of `width` per batch,
  // calls after_chunk(first batch, batch count) in the thread that evaluated the chunk, and hands the
  // results to add(first batch, batch count, results) in batch order: serially chunk by chunk, each
  // added while in cache; otherwise all in parallel into batch_out_, then added.
  template <class AfterChunk, class Add>
  void evaluate_and_add(AngleBatchFunction kernel, int rows, const VecX& x, AfterChunk after_chunk, Add add) const;

  StencilTerm<AngleKernel> scalar_;
  SimdLevel level_;
  AngleBatchParams params_;
  AngleBatchKernels kernels_;
  std::vector<int> offsets_;                         // the batches' coordinate offsets (angle_batch.hpp)
  mutable std::vector<double> batch_out_;            // a chunk's results serially, all in parallel; grown at first use
  mutable std::vector<AngleKernel::Mat> projected_;  // accumulate_hessian_pair's projected Hessians in parallel
};

}  // namespace fnopt
