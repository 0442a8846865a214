#pragma once
// Where the viewer's page comes from (docs/design.md §11): our own files (viewer/web, installed
// as PREFIX/share/fnopt/web) and three.js with its OrbitControls from Debian's libjs-three.
// These files, by their fixed names, and the viewed data are all the server ever sends.
#include <string>
#include <vector>

namespace fnopt {

struct WebAsset {
  std::string url;           // e.g. "/viewer.js"
  std::string file;          // its path on disk
  std::string content_type;  // e.g. "text/javascript"
};

// The page's files. Ours are looked for beside the binary first (PREFIX/bin/fnopt next to
// PREFIX/share/fnopt/web, after cmake --install), then in the source tree, as the shipped model
// is (methods/registry.cpp). Throws Error naming the file and the package to install if one is
// missing.
std::vector<WebAsset> find_web_assets();

}  // namespace fnopt
