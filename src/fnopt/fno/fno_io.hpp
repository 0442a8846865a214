#pragma once
// FNO2d weights on disk: one LibTorch archive (a zip file) holding
//   format       "fnopt-fno"        (what kind of file this is)
//   version      2                  (layout of this file, kFnoFileVersion; bumped on incompatible changes)
//   architecture "fno2d"            (which model the parameters belong to)
//   options/<name>                  every FNO2dOptions field that shapes the model
//   parameters/...                  the parameters, in torch::nn::Module::save's layout
//   checksum                        of the parameters, checked on load (from version 2)
// Files are written atomically (temporary file, then rename). Every way a file can be wrong
// (missing, not an archive, truncated, another format, version or architecture, parameters
// that do not fit the options) is one fnopt::Error "<path>: <problem>".
#include <string>

#include <fnopt/fno/fno2d.hpp>

namespace fnopt {

// Version 2 stores a checksum of the parameters, checked on load; version 1 files (no
// checksum) are still read.
inline constexpr int64_t kFnoFileVersion = 2;
inline constexpr int64_t kFnoFirstReadableVersion = 1;

void save_fno(const std::string& path, const FNO2d& model);

// The options stored in a weights file (validated), without loading the parameters.
FNO2dOptions load_fno_options(const std::string& path);

// A float model on the CPU with the stored options and parameters, spectral backend FFTW.
FNO2d load_fno(const std::string& path);

}  // namespace fnopt
