#pragma once
// The one generic assembly of every per-stencil energy (ipc-toolkit style): a Kernel evaluates
// energy, gradient and Hessian of one stencil on fixed-size Eigen types; StencilTerm gathers
// each stencil's coordinates, evaluates all stencils in parallel (OpenMP) into per-stencil
// buffers, and scatters serially (stencils share vertices, so a parallel scatter would race); on
// one thread it scatters each stencil as it is evaluated. The buffers are allocated once; a
// StencilTerm is not safe to evaluate from two threads.
#include <omp.h>

#include <array>
#include <string>
#include <tuple>
#include <vector>

#include <fnopt/cloth/energy_term.hpp>

namespace fnopt {

template <class Kernel>
class StencilTerm final : public EnergyTerm {
 public:
  static constexpr int N = Kernel::kVertices;
  // Below this many stencils a parallel region costs more than it saves.
  static constexpr long kParallelThreshold = 2048;
  using Stencil = std::array<int, N>;
  using LocalVec = typename Kernel::Vec;
  using LocalMat = typename Kernel::Mat;

  StencilTerm(std::string name, Kernel kernel, std::vector<Stencil> stencils)
      : name_(std::move(name)), kernel_(kernel), stencils_(std::move(stencils)) {}

  const std::string& name() const override { return name_; }
  const std::vector<Stencil>& stencils() const { return stencils_; }
  const Kernel& kernel() const { return kernel_; }

  // The stencil's coordinates of x, as the kernel takes them.
  static LocalVec gather(const VecX& x, const Stencil& stencil) {
    LocalVec local;
    for (int i = 0; i < N; ++i) local.template segment<3>(3 * i) = x.segment<3>(3 * stencil[i]);
    return local;
  }
  // On one thread each stencil's gradient or matrix is added while it is in registers and L1:
  // through the per-stencil buffers a fine cloth's angle stencils would write and read back tens
  // of megabytes per Hessian (docs/design.md §6). The sums run in the same order either way.
  static bool serial(long count) { return count < kParallelThreshold || omp_get_max_threads() == 1; }

  double energy(const VecX& x) const override {
    const long count = static_cast<long>(stencils_.size());
    double total = 0.0;
#pragma omp parallel for reduction(+ : total) schedule(static) if (count >= kParallelThreshold)
    for (long s = 0; s < count; ++s) total += kernel_.energy(gather(x, stencils_[s]));
    return total;
  }

  double accumulate_gradient(const VecX& x, VecX& grad) const override {
    return evaluate_and_add([&](long s, LocalVec& local) { return kernel_.gradient(gather(x, stencils_[s]), local); },
                            [&](long s, const LocalVec& local) {
                              for (int i = 0; i < N; ++i)
                                grad.segment<3>(3 * stencils_[s][i]) += local.template segment<3>(3 * i);
                            },
                            gradients_);
  }

  int register_hessian(HessianAssembly& assembly) const override {
    return assembly.add_stencils(stencils_.empty() ? nullptr : stencils_[0].data(), stencils_.size(), N);
  }

  void accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const override {
    evaluate_and_add(
        [&](long s, LocalMat& local) {
          kernel_.hessian(gather(x, stencils_[s]), local, project);
          return 0.0;
        },
        [&](long s, const LocalMat& local) { assembly.scatter<N>(handle, s, local); }, hessians_);
  }

  void accumulate_hessian_pair(const VecX& x, HessianAssembly& assembly, int handle) const override {
    evaluate_and_add(
        [&](long s, LocalMat& exact, LocalMat& projected) {
          kernel_.hessian_pair(gather(x, stencils_[s]), exact, projected);
          return 0.0;
        },
        [&](long s, const LocalMat& exact, const LocalMat& projected) {
          assembly.scatter_pair<N>(handle, s, exact, projected);
        },
        hessians_, projected_);
  }

 private:

  // evaluate(s, locals...) fills stencil s's results and returns its energy; add(s, locals...) adds them
  // to the sums, in stencil order. In parallel the results go through the buffers (one per result).
  // Returns the energies' total.
  template <class Evaluate, class Add, class... Local>
  double evaluate_and_add(Evaluate evaluate, Add add, std::vector<Local>&... buffers) const {
    const long count = static_cast<long>(stencils_.size());
    double total = 0.0;
    if (serial(count)) {
      std::tuple<Local...> locals;
      for (long s = 0; s < count; ++s)
        std::apply(
            [&](Local&... local) {
              total += evaluate(s, local...);
              add(s, local...);
            },
            locals);
      return total;
    }
    (buffers.resize(stencils_.size()), ...);
#pragma omp parallel for reduction(+ : total) schedule(static)
    for (long s = 0; s < count; ++s) total += evaluate(s, buffers[s]...);
    for (long s = 0; s < count; ++s) add(s, buffers[s]...);
    return total;
  }

  std::string name_;
  Kernel kernel_;
  std::vector<Stencil> stencils_;
  mutable std::vector<LocalVec> gradients_;  // the buffers of the parallel loops, allocated at their first use
  mutable std::vector<LocalMat> hessians_, projected_;
};

}  // namespace fnopt
