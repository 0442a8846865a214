#include <fnopt/fno/fno_io.hpp>

#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <type_traits>

#include <fnopt/util/error.hpp>
#include <fnopt/util/fnv_hash.hpp>

namespace fnopt {
namespace {

constexpr const char* kFormat = "fnopt-fno";
constexpr const char* kArchitecture = "fno2d";

[[noreturn]] void fail(const std::string& path, const std::string& problem) { throw Error(path + ": " + problem); }

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

// FNV-1a (64 bit) over every parameter's values, in the model's parameter order: stored with
// the weights, so that a file whose bytes changed (a bad copy, a disk error) is refused rather
// than run with other weights. LibTorch's zip reader does not check its own CRCs.
std::string parameter_checksum(const FNO2dImpl& model) {
  Fnv1aHash hash;
  for (const auto& parameter : model.named_parameters()) {
    const torch::Tensor values = parameter.value().detach().contiguous().to(torch::kFloat);
    hash.add(values.data_ptr(), static_cast<std::size_t>(values.numel()) * sizeof(float));
  }
  return hash.hex();
}

std::string shape_text(torch::IntArrayRef sizes) {
  std::ostringstream s;
  s << sizes;
  return s.str();
}

// A LibTorch archive is a zip file: anything else is rejected before LibTorch parses it.
bool starts_like_zip(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  char magic[4] = {};
  file.read(magic, sizeof magic);
  return file.gcount() == sizeof magic && std::memcmp(magic, "PK\x03\x04", sizeof magic) == 0;
}

// Opens the archive and checks format, version and architecture.
torch::serialize::InputArchive open_archive(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path, "no such FNO weights file");
  if (!std::ifstream(path, std::ios::binary)) fail(path, "cannot open the FNO weights file");
  if (!starts_like_zip(path)) fail(path, "not an fnopt FNO weights file (not a LibTorch archive)");
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(path, torch::Device(torch::kCPU));
  } catch (const c10::Error& e) {
    fail(path, "truncated or corrupt FNO weights file (" + first_line(e.what_without_backtrace()) + ")");
  }
  c10::IValue value;
  if (!archive.try_read("format", value) || !value.isString() || value.toStringRef() != kFormat)
    fail(path, std::string("not an fnopt FNO weights file (no \"") + kFormat + "\" format tag)");
  if (!archive.try_read("version", value) || !value.isInt()) fail(path, "FNO weights file without a format version");
  if (value.toInt() < kFnoFirstReadableVersion || value.toInt() > kFnoFileVersion)
    fail(path, "FNO weights format version " + std::to_string(value.toInt()) + ", this build reads versions " +
                   std::to_string(kFnoFirstReadableVersion) + " to " + std::to_string(kFnoFileVersion));
  if (!archive.try_read("architecture", value) || !value.isString())
    fail(path, "FNO weights file without an architecture");
  if (value.toStringRef() != kArchitecture)
    fail(path,
         "FNO weights of architecture \"" + value.toStringRef() + "\", this build reads \"" + kArchitecture + "\"");
  return archive;
}

FNO2dOptions read_options(torch::serialize::InputArchive& archive, const std::string& path) {
  torch::serialize::InputArchive stored;
  if (!archive.try_read("options", stored)) fail(path, "FNO weights file without options");
  FNO2dOptions options;
  for_each_architecture_option(options, [&](const char* name, auto& field) {
    using Field = std::decay_t<decltype(field)>;
    c10::IValue value;
    const bool found = stored.try_read(name, value);
    bool typed = false;
    if constexpr (std::is_same_v<Field, bool>) {
      typed = found && value.isBool();
      if (typed) field = value.toBool();
    } else if constexpr (std::is_same_v<Field, double>) {
      typed = found && value.isDouble();
      if (typed) field = value.toDouble();
    } else {
      typed = found && value.isInt();
      if (typed) field = value.toInt();
    }
    if (!typed) fail(path, std::string("FNO option \"") + name + "\" missing or of the wrong type");
  });
  try {
    validate(options);
  } catch (const Error& e) {
    fail(path, e.what());
  }
  return options;
}

// The tensor saved under a dotted parameter name ("spectral_0.weight": nested archive
// "spectral_0", key "weight"), or an undefined tensor.
torch::Tensor read_parameter(torch::serialize::InputArchive& parameters, const std::string& name) {
  torch::serialize::InputArchive nested;
  torch::serialize::InputArchive* current = &parameters;
  size_t begin = 0;
  for (size_t dot = name.find('.'); dot != std::string::npos; dot = name.find('.', begin)) {
    torch::serialize::InputArchive child;
    if (!current->try_read(name.substr(begin, dot - begin), child)) return {};
    nested = std::move(child);
    current = &nested;
    begin = dot + 1;
  }
  torch::Tensor tensor;
  current->try_read(name.substr(begin), tensor);
  return tensor;
}

void read_parameters(torch::serialize::InputArchive& archive, const std::string& path, FNO2dImpl& model) {
  torch::serialize::InputArchive stored;
  if (!archive.try_read("parameters", stored)) fail(path, "FNO weights file without parameters");
  torch::NoGradGuard no_grad;
  for (auto& parameter : model.named_parameters()) {
    const torch::Tensor value = read_parameter(stored, parameter.key());
    if (!value.defined()) fail(path, "FNO parameter \"" + parameter.key() + "\" missing");
    if (value.sizes() != parameter.value().sizes())
      fail(path, "FNO parameter \"" + parameter.key() + "\" has shape " + shape_text(value.sizes()) +
                     ", its options need " + shape_text(parameter.value().sizes()));
    parameter.value().copy_(value);
  }
  // Version 2 on: the parameters must hash to the stored checksum.
  c10::IValue version, checksum;
  archive.try_read("version", version);
  if (version.toInt() < 2) return;
  if (!archive.try_read("checksum", checksum) || !checksum.isString())
    fail(path, "FNO weights file without its checksum");
  if (checksum.toStringRef() != parameter_checksum(model))
    fail(path, "corrupt FNO weights file: the parameters do not match their checksum");
}

// Runs a read of `path`, turning any LibTorch error into one fnopt::Error.
template <typename Read>
auto guarded(const std::string& path, Read&& read) {
  try {
    return read();
  } catch (const c10::Error& e) {
    fail(path, "corrupt FNO weights file (" + first_line(e.what_without_backtrace()) + ")");
  }
}

}  // namespace

void save_fno(const std::string& path, const FNO2d& model) {
  torch::serialize::OutputArchive archive;
  archive.write("format", c10::IValue(std::string(kFormat)));
  archive.write("version", c10::IValue(kFnoFileVersion));
  archive.write("architecture", c10::IValue(std::string(kArchitecture)));
  torch::serialize::OutputArchive options(archive.compilation_unit());
  for_each_architecture_option(model->options,
                               [&](const char* name, const auto& field) { options.write(name, c10::IValue(field)); });
  archive.write("options", options);
  torch::serialize::OutputArchive parameters(archive.compilation_unit());
  model->save(parameters);
  archive.write("parameters", parameters);
  archive.write("checksum", c10::IValue(parameter_checksum(*model)));

  // Readers never see a half-written file: write a sibling, then rename over the target.
  const std::string temporary = path + ".tmp." + std::to_string(::getpid());
  try {
    archive.save_to(temporary);
  } catch (const c10::Error& e) {
    std::remove(temporary.c_str());
    fail(path, "cannot write the FNO weights file (" + first_line(e.what_without_backtrace()) + ")");
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    fail(path, "cannot write the FNO weights file (" + reason + ")");
  }
}

FNO2dOptions load_fno_options(const std::string& path) {
  return guarded(path, [&] {
    torch::serialize::InputArchive archive = open_archive(path);
    return read_options(archive, path);
  });
}

FNO2d load_fno(const std::string& path) {
  return guarded(path, [&] {
    torch::serialize::InputArchive archive = open_archive(path);
    FNO2d model(read_options(archive, path));
    read_parameters(archive, path, *model);
    return model;
  });
}

}  // namespace fnopt
