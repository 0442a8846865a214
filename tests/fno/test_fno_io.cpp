// FNO weights on disk: save → load round trip, and each kind of bad file rejected with its
// own one-line fnopt::Error naming the file.
#include <gtest/gtest.h>
#include <torch/torch.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <fnopt/fno/fno_io.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

namespace fs = std::filesystem;

FNO2dOptions small_options() {
  return FNO2dOptions().width(8).lifting_channels(16).projection_channels(8).modes_x(4).modes_y(6);
}

class FnoWeightsFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("fnopt_fno_io_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Expects load_fno (and load_fno_options unless the problem is in the parameters, which it
  // does not read) to throw an Error naming the file and the problem.
  void expect_rejected(const std::string& file, const std::string& problem, bool options_too = true) const {
    for (int which = 0; which < (options_too ? 2 : 1); ++which) {
      try {
        if (which == 0)
          load_fno(file);
        else
          load_fno_options(file);
        ADD_FAILURE() << "loaded " << file;
      } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(file + ": ", 0), 0u) << message;
        EXPECT_NE(message.find(problem), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      }
    }
  }

  // An archive laid out like save_fno's, with chosen header values, options and parameters.
  void write_archive(const std::string& file, const std::string& format, int64_t version,
                     const std::string& architecture, const FNO2d& options_of, const FNO2d& parameters_of) const {
    torch::serialize::OutputArchive archive;
    archive.write("format", c10::IValue(format));
    archive.write("version", c10::IValue(version));
    archive.write("architecture", c10::IValue(architecture));
    torch::serialize::OutputArchive options(archive.compilation_unit());
    const FNO2dOptions& o = options_of->options;
    options.write("in_channels", c10::IValue(o.in_channels()));
    options.write("out_channels", c10::IValue(o.out_channels()));
    options.write("width", c10::IValue(o.width()));
    options.write("fourier_layers", c10::IValue(o.fourier_layers()));
    options.write("modes_x", c10::IValue(o.modes_x()));
    options.write("modes_y", c10::IValue(o.modes_y()));
    options.write("lifting_channels", c10::IValue(o.lifting_channels()));
    options.write("projection_channels", c10::IValue(o.projection_channels()));
    options.write("scale_head", c10::IValue(o.scale_head()));
    options.write("scale_head_layer", c10::IValue(o.scale_head_layer()));
    options.write("padding_fraction", c10::IValue(o.padding_fraction()));
    archive.write("options", options);
    torch::serialize::OutputArchive parameters(archive.compilation_unit());
    parameters_of->save(parameters);
    archive.write("parameters", parameters);
    archive.save_to(file);
  }

  fs::path dir_;
};

TEST_F(FnoWeightsFile, SaveLoadGivesIdenticalOutputs) {
  torch::manual_seed(1);
  FNO2d model(small_options().padding_fraction(0.125).scale_head_layer(2));
  const std::string file = path("model.pt");
  save_fno(file, model);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1)
      << "the temporary file was left behind";

  FNO2d loaded = load_fno(file);
  const FNO2dOptions stored = load_fno_options(file);
  EXPECT_EQ(stored.width(), 8);
  EXPECT_EQ(stored.modes_y(), 6);
  EXPECT_EQ(stored.scale_head_layer(), 2);
  EXPECT_EQ(loaded->options.padding_fraction(), 0.125);

  torch::NoGradGuard no_grad;
  const torch::Tensor x = torch::randn({2, 3, 17, 12});
  const FNO2dOutput a = model->forward(x), b = loaded->forward(x);
  EXPECT_TRUE(torch::equal(a.field, b.field));
  EXPECT_TRUE(torch::equal(a.scale, b.scale));
}

TEST_F(FnoWeightsFile, SavingOverAnExistingFileReplacesIt) {
  const std::string file = path("model.pt");
  save_fno(file, FNO2d(small_options()));
  save_fno(file, FNO2d(small_options().width(4)));
  EXPECT_EQ(load_fno_options(file).width(), 4);
}

TEST_F(FnoWeightsFile, UnwritablePathIsAnError) {
  const std::string file = path("no/such/dir/model.pt");
  try {
    save_fno(file, FNO2d(small_options()));
    ADD_FAILURE() << "saved";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(file + ": cannot write"), std::string::npos) << e.what();
  }
}

TEST_F(FnoWeightsFile, MissingFileIsRejected) { expect_rejected(path("absent.pt"), "no such FNO weights file"); }

TEST_F(FnoWeightsFile, TruncatedFileIsRejected) {
  const std::string file = path("truncated.pt");
  save_fno(file, FNO2d(small_options()));
  fs::resize_file(file, fs::file_size(file) / 2);
  expect_rejected(file, "truncated or corrupt FNO weights file");
}

TEST_F(FnoWeightsFile, GarbageBytesAreRejected) {
  const std::string file = path("garbage.pt");
  std::ofstream(file, std::ios::binary) << "\x89HDF\r\n this is not a model, just bytes";
  expect_rejected(file, "not an fnopt FNO weights file (not a LibTorch archive)");
}

TEST_F(FnoWeightsFile, OtherLibTorchArchiveIsRejected) {
  const std::string file = path("tensor.pt");
  torch::save(torch::ones({3}), file);
  expect_rejected(file, "not an fnopt FNO weights file (no \"fnopt-fno\" format tag)");
}

TEST_F(FnoWeightsFile, OtherFormatVersionIsRejected) {
  const std::string file = path("v3.pt");
  FNO2d model(small_options());
  write_archive(file, "fnopt-fno", 3, "fno2d", model, model);
  expect_rejected(file, "FNO weights format version 3, this build reads versions 1 to 2");
}

TEST_F(FnoWeightsFile, VersionOneFilesWithoutAChecksumStillLoad) {
  const std::string file = path("v1.pt");
  torch::manual_seed(3);
  FNO2d model(small_options());
  write_archive(file, "fnopt-fno", 1, "fno2d", model, model);
  const FNO2d loaded = load_fno(file);
  EXPECT_TRUE(torch::equal(loaded->parameters()[0], model->parameters()[0]));
}

TEST_F(FnoWeightsFile, AVersionTwoFileWithoutItsChecksumIsRejected) {
  const std::string file = path("v2.pt");
  FNO2d model(small_options());
  write_archive(file, "fnopt-fno", 2, "fno2d", model, model);
  expect_rejected(file, "FNO weights file without its checksum", false);
}

// Bytes changed inside the shipped model's weights (a bad copy): LibTorch's zip reader loads
// them without a complaint; the stored checksum refuses them.
TEST_F(FnoWeightsFile, ChangedBytesInTheShippedModelAreRejected) {
  const std::string shipped = std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt";
  ASSERT_NO_THROW(load_fno(shipped));
  const std::string file = path("flipped.pt");
  fs::copy_file(shipped, file);
  std::fstream bytes(file, std::ios::in | std::ios::out | std::ios::binary);
  const auto size = static_cast<std::streamoff>(fs::file_size(file));
  for (std::streamoff at = size / 2; at < size / 2 + 4096; at += 64) {  // 64 bytes in the weights
    char c = 0;
    bytes.seekg(at);
    bytes.read(&c, 1);
    c = static_cast<char>(c ^ 0x5a);
    bytes.seekp(at);
    bytes.write(&c, 1);
  }
  bytes.close();
  expect_rejected(file, "corrupt FNO weights file", false);
}

TEST_F(FnoWeightsFile, OtherArchitectureIsRejected) {
  const std::string file = path("fno3d.pt");
  FNO2d model(small_options());
  write_archive(file, "fnopt-fno", 1, "fno3d", model, model);
  expect_rejected(file, "FNO weights of architecture \"fno3d\", this build reads \"fno2d\"");
}

TEST_F(FnoWeightsFile, ParametersOfAnotherShapeAreRejected) {
  const std::string file = path("mismatch.pt");
  write_archive(file, "fnopt-fno", 1, "fno2d", FNO2d(small_options()), FNO2d(small_options().width(4)));
  expect_rejected(file, "FNO parameter \"lift_out.weight\" has shape [4, 16], its options need [8, 16]", false);
}

TEST_F(FnoWeightsFile, MissingParameterIsRejected) {
  const std::string file = path("headless.pt");
  write_archive(file, "fnopt-fno", 1, "fno2d", FNO2d(small_options()), FNO2d(small_options().scale_head(false)));
  expect_rejected(file, "FNO parameter \"scale_head.weight\" missing", false);
}

TEST_F(FnoWeightsFile, InvalidStoredOptionsAreRejected) {
  const std::string file = path("invalid.pt");
  FNO2d model(small_options());
  model->options.width(0);
  write_archive(file, "fnopt-fno", 1, "fno2d", model, model);
  expect_rejected(file, "FNO2d option width: must be positive, got 0");
}

}  // namespace
}  // namespace fnopt
