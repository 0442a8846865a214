#include <fnopt/io/hdf5_file.hpp>

#include <filesystem>

#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// Closes an HDF5 identifier when it goes out of scope.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

}  // namespace

Hdf5File::Hdf5File(const std::string& path, Mode mode) : path_(path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  if (mode == Mode::Read) {
    if (!std::filesystem::is_regular_file(path)) throw Error(path + ": no such file");
    if (H5Fis_hdf5(path.c_str()) <= 0) throw Error(path + ": not an HDF5 file");
    file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  } else {
    file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  }
  if (file_ < 0) throw Error(path + ": cannot " + (mode == Mode::Read ? "open" : "create") + " the HDF5 file");
}

Hdf5File::~Hdf5File() {
  if (file_ >= 0) H5Fclose(file_);
}

void Hdf5File::write_raw(const std::string& name, const std::vector<hsize_t>& dims, hid_t file_type, hid_t memory_type,
                         const void* data) {
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Handle set(H5Dcreate2(file_, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (!set.valid() || H5Dwrite(set.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw Error(path_ + ": cannot write dataset '" + name + "'");
}

void Hdf5File::write(const std::string& name, const std::vector<hsize_t>& dims, const float* data) {
  write_raw(name, dims, H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, data);
}
void Hdf5File::write(const std::string& name, const std::vector<hsize_t>& dims, const double* data) {
  write_raw(name, dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data);
}
void Hdf5File::write(const std::string& name, const std::vector<hsize_t>& dims, const int* data) {
  write_raw(name, dims, H5T_STD_I32LE, H5T_NATIVE_INT, data);
}

bool Hdf5File::has(const std::string& name) const { return H5Lexists(file_, name.c_str(), H5P_DEFAULT) > 0; }

std::vector<std::string> Hdf5File::names() const {
  std::vector<std::string> names;
  auto add = [](hid_t, const char* name, const H5L_info_t*, void* out) -> herr_t {
    static_cast<std::vector<std::string>*>(out)->push_back(name);
    return 0;
  };
  if (H5Literate(file_, H5_INDEX_NAME, H5_ITER_INC, nullptr, add, &names) < 0)
    throw Error(path_ + ": cannot list its datasets");
  return names;
}

std::vector<hsize_t> Hdf5File::dims(const std::string& name) const {
  Handle set(H5Dopen2(file_, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!set.valid()) throw Error(path_ + ": missing dataset '" + name + "'");
  Handle space(H5Dget_space(set.get()), H5Sclose);
  std::vector<hsize_t> d(std::max(0, H5Sget_simple_extent_ndims(space.get())));
  H5Sget_simple_extent_dims(space.get(), d.data(), nullptr);
  return d;
}

std::size_t Hdf5File::element_count(const std::string& name) const {
  std::size_t n = 1;
  for (hsize_t d : dims(name)) n *= d;
  return n;
}

void Hdf5File::read_raw(const std::string& name, hid_t memory_type, void* data) const {
  Handle set(H5Dopen2(file_, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!set.valid() || H5Dread(set.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw Error(path_ + ": cannot read dataset '" + name + "'");
}

std::vector<float> Hdf5File::read_floats(const std::string& name) const {
  std::vector<float> v(element_count(name));
  read_raw(name, H5T_NATIVE_FLOAT, v.data());
  return v;
}
std::vector<double> Hdf5File::read_doubles(const std::string& name) const {
  std::vector<double> v(element_count(name));
  read_raw(name, H5T_NATIVE_DOUBLE, v.data());
  return v;
}
std::vector<int> Hdf5File::read_ints(const std::string& name) const {
  std::vector<int> v(element_count(name));
  read_raw(name, H5T_NATIVE_INT, v.data());
  return v;
}

void Hdf5File::write_attribute(const std::string& name, hid_t file_type, hid_t memory_type, const void* value,
                               const std::string& object) {
  Handle target(H5Oopen(file_, object.c_str(), H5P_DEFAULT), H5Oclose);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(
      target.valid() ? H5Acreate2(target.get(), name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT) : -1,
      H5Aclose);
  if (!attr.valid() || H5Awrite(attr.get(), memory_type, value) < 0)
    throw Error(path_ + ": cannot write attribute '" + name + "' of '" + object + "'");
}

void Hdf5File::set_attribute(const std::string& name, const std::string& value, const std::string& object) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), std::max<std::size_t>(1, value.size()));
  write_attribute(name, type.get(), type.get(), value.c_str(), object);
}

void Hdf5File::set_attribute(const std::string& name, double value, const std::string& object) {
  write_attribute(name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value, object);
}

void Hdf5File::set_attribute(const std::string& name, int value, const std::string& object) {
  write_attribute(name, H5T_STD_I32LE, H5T_NATIVE_INT, &value, object);
}

int Hdf5File::int_attribute(const std::string& name) const {
  Handle attr(H5Aopen(file_, name.c_str(), H5P_DEFAULT), H5Aclose);
  int value = 0;
  if (!attr.valid() || H5Aread(attr.get(), H5T_NATIVE_INT, &value) < 0)
    throw Error(path_ + ": cannot read attribute '" + name + "'");
  return value;
}

bool Hdf5File::has_attribute(const std::string& name) const { return H5Aexists(file_, name.c_str()) > 0; }

std::string Hdf5File::string_attribute(const std::string& name, const std::string& object) const {
  Handle attr(H5Aopen_by_name(file_, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) throw Error(path_ + ": missing attribute '" + name + "'");
  Handle type(H5Aget_type(attr.get()), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_STRING) throw Error(path_ + ": attribute '" + name + "' is not a string");
  if (H5Tis_variable_str(type.get()) > 0) {
    char* text = nullptr;
    Handle memory(H5Tget_native_type(type.get(), H5T_DIR_ASCEND), H5Tclose);
    if (H5Aread(attr.get(), memory.get(), &text) < 0) throw Error(path_ + ": cannot read attribute '" + name + "'");
    std::string value = text ? text : "";
    H5free_memory(text);
    return value;
  }
  std::string value(H5Tget_size(type.get()), '\0');
  if (H5Aread(attr.get(), type.get(), value.data()) < 0) throw Error(path_ + ": cannot read attribute '" + name + "'");
  return value.substr(0, value.find('\0'));
}

}  // namespace fnopt
