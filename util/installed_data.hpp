#pragma once
// Where fnopt's data files are (the shipped model, the viewer's page): installed beside the
// binary (PREFIX/bin/fnopt and PREFIX/share/fnopt/..., `cmake --install`), else in the source
// tree the binary was built from. So an installed binary runs from any directory.
#include <string>

namespace fnopt {

// PREFIX/share/fnopt/<installed> if that file exists, else SOURCE/<in_source>.
std::string installed_data_path(const std::string& installed, const std::string& in_source);

}  // namespace fnopt
