#pragma once
// A thin RAII layer over the HDF5 C API: whole-dataset reads and writes of numbers, and string
// and scalar attributes on the root group. Every failure throws Error naming the file and the
// dataset; HDF5's own error printing is switched off.
#include <hdf5.h>

#include <string>
#include <vector>

namespace fnopt {

class Hdf5File {
 public:
  enum class Mode { Read, Create };
  Hdf5File(const std::string& path, Mode mode);
  ~Hdf5File();
  Hdf5File(const Hdf5File&) = delete;
  Hdf5File& operator=(const Hdf5File&) = delete;

  const std::string& path() const { return path_; }

  void write(const std::string& name, const std::vector<hsize_t>& dims, const float* data);
  void write(const std::string& name, const std::vector<hsize_t>& dims, const double* data);
  void write(const std::string& name, const std::vector<hsize_t>& dims, const int* data);
  bool has(const std::string& name) const;
  // The names of the root group's members, in name order.
  std::vector<std::string> names() const;
  std::vector<hsize_t> dims(const std::string& name) const;
  std::vector<float> read_floats(const std::string& name) const;    // converts on read
  std::vector<double> read_doubles(const std::string& name) const;  // converts on read
  std::vector<int> read_ints(const std::string& name) const;

  // Attributes of the root group, or of the dataset `object` (e.g. a unit).
  void set_attribute(const std::string& name, const std::string& value, const std::string& object = "/");
  void set_attribute(const std::string& name, double value, const std::string& object = "/");
  void set_attribute(const std::string& name, int value, const std::string& object = "/");
  bool has_attribute(const std::string& name) const;
  std::string string_attribute(const std::string& name, const std::string& object = "/") const;
  int int_attribute(const std::string& name) const;  // converts on read

 private:
  void write_raw(const std::string& name, const std::vector<hsize_t>& dims, hid_t file_type, hid_t memory_type,
                 const void* data);
  void read_raw(const std::string& name, hid_t memory_type, void* data) const;
  void write_attribute(const std::string& name, hid_t file_type, hid_t memory_type, const void* value,
                       const std::string& object);
  std::size_t element_count(const std::string& name) const;

  std::string path_;
  hid_t file_ = -1;
};

}  // namespace fnopt
