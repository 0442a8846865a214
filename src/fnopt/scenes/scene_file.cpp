// The scene file format and single settings, on the table of scene keys (scene_keys.hpp).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <fnopt/scenes/scene.hpp>
#include <fnopt/scenes/scene_keys.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

namespace fs = std::filesystem;

// The line without its comment: '#' at the start or after a blank, so that "file.csv#motion"
// keeps its '#'.
std::string_view without_comment(std::string_view line) {
  for (std::size_t at = line.find('#'); at != std::string_view::npos; at = line.find('#', at + 1))
    if (at == 0 || line[at - 1] == ' ' || line[at - 1] == '\t') return line.substr(0, at);
  return line;
}

}  // namespace

void apply_scene_setting(Scene& scene, const std::string& key, const std::string& value) {
  const SceneKey* spec = find_scene_key(key);
  require(spec != nullptr, key, "unknown setting (valid: " + scene_key_names() + ")");
  const std::string text(trim(value));
  // An empty list or path clears it, so that a later file or flag can undo an earlier one.
  require(!text.empty() || spec->empty_clears(), key, "expected a value after '='");
  spec->codec.apply(scene, key, text);
  resolve_repulsion(scene);  // handles, handle-vertices, repulsion and material all bear on it
}

namespace {

// The settings of a scene file's lines, on top of `base`; `name` starts every error message and
// relative paths are taken relative to `directory` (none if it is empty).
Scene read_scene_lines(std::istream& in, const std::string& name, const std::string& directory, Scene base) {
  std::string line;
  int number = 0;
  std::map<std::string, int> seen;  // key -> line
  while (std::getline(in, line)) {
    ++number;
    const std::string where = name + ":" + std::to_string(number) + ": ";
    // A binary file is refused without echoing its bytes to the terminal.
    if (!std::all_of(line.begin(), line.end(), [](unsigned char c) { return c >= 32 || c == '\t' || c == '\r'; }))
      throw Error(where + "not a text scene file (control or binary bytes)");
    const auto content = trim(without_comment(line));
    if (content.empty()) continue;
    const auto equals = content.find('=');
    if (equals == std::string_view::npos) {
      const std::string shown(content.substr(0, 60));
      throw Error(where + "expected 'key = value', got '" + shown + (content.size() > 60 ? "...'" : "'"));
    }
    const std::string key(trim(content.substr(0, equals)));
    std::string value(trim(content.substr(equals + 1)));
    if (key.empty()) throw Error(where + "missing key before '='");
    const SceneKey* spec = find_scene_key(key);
    if (!seen.emplace(key, number).second && !(spec && spec->repeatable()))
      throw Error(where + key + ": given twice (first on line " + std::to_string(seen[key]) + ")");
    if (spec && !spec->accepted_by(kSceneFile)) throw Error(where + key + ": not a scene-file key");
    if (spec && spec->codec.rebase) value = spec->codec.rebase(directory, value);
    try {
      apply_scene_setting(base, key, value);
    } catch (const Error& e) {
      throw Error(where + e.what());
    }
  }
  return base;
}

}  // namespace

Scene load_scene_file(const std::string& path, Scene base) {
  std::error_code ignored;
  std::ifstream in(path);
  require(in && !fs::is_directory(path, ignored), "scene", "cannot open '" + path + "'");
  base = read_scene_lines(in, path, fs::path(path).parent_path().string(), std::move(base));
  require(!in.bad(), "scene", "cannot read '" + path + "'");
  return base;
}

Scene load_scene_text(const std::string& text, const std::string& name, Scene base) {
  std::istringstream in(text);
  return read_scene_lines(in, name, {}, std::move(base));
}

std::string to_scene_text(const Scene& scene) {
  std::string text = "# fnopt scene\n";
  for (const SceneKey& key : scene_keys())
    for (const std::string& line : scene_file_lines(key, scene)) text += line + "\n";
  return text;
}

}  // namespace fnopt
