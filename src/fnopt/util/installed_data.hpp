#pragma once
// Where fnopt's data files are (the shipped model, the viewer's page): installed under
// PREFIX/share/fnopt (`cmake --install`) above the running binary (PREFIX/bin/fnopt) or above the
// shared object this code is linked into (the Python module under PREFIX/lib/...), else in the
// source tree fnopt was built from. So an installed binary or module runs from any directory.
#include <string>

namespace fnopt {

// P/share/fnopt/<installed> for the nearest ancestor P of the binary or of this code's shared
// object where that file exists, else SOURCE/<in_source>.
std::string installed_data_path(const std::string& installed, const std::string& in_source);

// The running executable's path (/proc/self/exe), empty where it cannot be read.
std::string executable_path();

}  // namespace fnopt
