#include <fnopt/fno/blas_info.hpp>

#include <dlfcn.h>

#include <torch/torch.h>

namespace fnopt::fno {

std::string runtime_blas() {
  // OpenBLAS exports openblas_get_config; the reference BLAS does not.
  using ConfigFn = char* (*)();
  auto config = reinterpret_cast<ConfigFn>(dlsym(RTLD_DEFAULT, "openblas_get_config"));
  if (config) return config();  // "OpenBLAS 0.3.21 ... USE_OPENMP Haswell ..."
  return "not OpenBLAS (dense layers will be 5-15x slower: install libopenblas0-openmp)";
}

std::string torch_blas_info() {
  const std::string config = torch::show_config();
  const auto begin = config.find("BLAS_INFO=");
  if (begin == std::string::npos) return "BLAS_INFO unknown";
  return config.substr(begin, config.find(',', begin) - begin);
}

}  // namespace fnopt::fno
