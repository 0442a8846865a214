#include <fnopt/contact/mesh_source.hpp>

namespace fnopt {
namespace {

thread_local const MeshFrames* stored_meshes = nullptr;

}  // namespace

std::vector<TriangleMesh> load_mesh_frames(const std::string& source, bool sequence) {
  if (stored_meshes) {
    const auto it = stored_meshes->find(source);
    if (it != stored_meshes->end()) return it->second;
  }
  return sequence ? read_obj_sequence(source) : std::vector<TriangleMesh>{read_obj_mesh(source)};
}

StoredMeshes::StoredMeshes(MeshFrames meshes) : meshes_(std::move(meshes)), previous_(stored_meshes) {
  stored_meshes = &meshes_;
}

StoredMeshes::~StoredMeshes() { stored_meshes = previous_; }

}  // namespace fnopt
