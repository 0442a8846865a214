#include <fnopt/contact/obstacle_spec.hpp>

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include <fnopt/contact/mesh_source.hpp>

#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// The key=value words after the shape, each key once.
class SpecKeys {
 public:
  SpecKeys(std::istringstream& words, const std::string& shape) : shape_(shape) {
    std::string word;
    while (words >> word) {
      const auto eq = word.find('=');
      fail_unless(eq != std::string::npos && eq > 0, "expected key=value, got '" + word + "'");
      const std::string key = word.substr(0, eq);
      fail_unless(values_.emplace(key, word.substr(eq + 1)).second, "key '" + key + "' given twice");
    }
  }

  // Fails on any key a shape does not take.
  void only(const std::vector<std::string>& keys) const {
    for (const auto& [key, value] : values_) {
      bool known = false;
      for (const auto& k : keys) known = known || k == key;
      fail_unless(known, "unknown key '" + key + "' for a " + shape_ + " (" + joined(keys) + ")");
    }
  }
  bool has(const std::string& key) const { return values_.count(key) > 0; }
  const std::string& text(const std::string& key) const {
    const auto it = values_.find(key);
    fail_unless(it != values_.end(), "a " + shape_ + " needs " + key + "=");
    return it->second;
  }
  double number(const std::string& key) const {
    double value = 0.0;
    fail_unless(parse_double(text(key), value), key + "='" + text(key) + "' is not a number");
    fail_unless(std::isfinite(value), key + "=" + text(key) + " is not finite");
    return value;
  }
  Vec3 point(const std::string& key) const {
    const auto cells = split(text(key), ',');
    fail_unless(cells.size() == 3, key + "='" + text(key) + "' is not three numbers X,Y,Z");
    Vec3 p;
    for (int c = 0; c < 3; ++c) {
      fail_unless(parse_double(cells[c], p[c]), key + "='" + text(key) + "' is not three numbers X,Y,Z");
      fail_unless(std::isfinite(p[c]), key + "=" + text(key) + " is not finite");
    }
    return p;
  }

  static void fail_unless(bool ok, const std::string& problem) { require(ok, "obstacle", problem); }

 private:
  std::string shape_;
  std::map<std::string, std::string> values_;
};

// The shape's own Error (e.g. "sphere.radius: must be ...") as the obstacle's one line.
template <class Build>
Obstacle built(Build build) {
  try {
    return build();
  } catch (const Error& e) {
    if (e.field() == "obstacle") throw;
    throw Error("obstacle", e.what());
  }
}

// A mesh: file=PATH.obj or sequence=PREFIX fps=F, with scale=S and offset=X,Y,Z (mesh_shape.hpp).
Obstacle mesh_obstacle(const SpecKeys& keys) {
  const bool sequence = keys.has("sequence");
  SpecKeys::fail_unless(sequence || keys.has("file"), "a mesh needs file=PATH.obj or sequence=PREFIX fps=F");
  SpecKeys::fail_unless(!(sequence && keys.has("file")), "give file= or sequence=, not both");
  SpecKeys::fail_unless(sequence || !keys.has("fps"), "fps= is for a sequence");
  std::error_code ignored;
  const std::string source = std::filesystem::absolute(keys.text(sequence ? "sequence" : "file"), ignored).string();
  const double scale = keys.has("scale") ? keys.number("scale") : 1.0;
  const Vec3 offset = keys.has("offset") ? keys.point("offset") : Vec3::Zero();
  auto frames = load_mesh_frames(source, sequence);
  auto shape = std::make_shared<const MeshShape>(sequence ? MeshShape::sequence(frames, keys.number("fps"), scale, offset)
                                                          : MeshShape::single(frames.front(), scale, offset));
  return Obstacle::mesh(std::move(shape), source);
}

}  // namespace

Obstacle parse_obstacle(const std::string& spec) {
  std::istringstream words(spec);
  std::string shape;
  words >> shape;
  SpecKeys::fail_unless(!shape.empty(), "empty spec (sphere, plane, box, capsule or mesh and its keys)");
  const std::vector<std::string> common = {"friction", "motion", "path"};
  auto with_common = [&](std::vector<std::string> keys) {
    keys.insert(keys.end(), common.begin(), common.end());
    return keys;
  };
  SpecKeys keys(words, shape);
  Obstacle obstacle = built([&] {
    if (shape == "sphere") {
      keys.only(with_common({"center", "radius"}));
      return Obstacle::sphere(keys.point("center"), keys.number("radius"));
    }
    if (shape == "plane") {
      keys.only(with_common({"point", "normal"}));
      return Obstacle::plane(keys.point("point"), keys.point("normal"));
    }
    if (shape == "box") {
      keys.only(with_common({"center", "size", "rounding"}));
      return Obstacle::box(keys.point("center"), keys.point("size"), keys.has("rounding") ? keys.number("rounding") : 0.0);
    }
    if (shape == "capsule") {
      keys.only(with_common({"a", "b", "radius"}));
      return Obstacle::capsule(keys.point("a"), keys.point("b"), keys.number("radius"));
    }
    if (shape == "mesh") {
      keys.only(with_common({"file", "sequence", "fps", "scale", "offset"}));
      return mesh_obstacle(keys);
    }
    throw Error("obstacle", "unknown shape '" + shape + "' (sphere, plane, box, capsule, mesh)");
  });
  SpecKeys::fail_unless(!(keys.has("motion") && keys.has("path")), "give motion= or path=, not both");
  built([&] {
    if (keys.has("friction")) obstacle.with_friction(keys.number("friction"));
    if (keys.has("motion")) obstacle.with_motion(ObstacleMotion::named(keys.text("motion"), obstacle.point()));
    if (keys.has("path")) obstacle.with_motion(ObstacleMotion::path(keys.text("path")));
    return obstacle;
  });
  return obstacle;
}

std::vector<Obstacle> parse_obstacles(const std::string& specs) {
  std::vector<Obstacle> obstacles;
  for (auto piece : split(specs, ';'))
    if (!trim(piece).empty()) obstacles.push_back(parse_obstacle(std::string(trim(piece))));
  return obstacles;
}

}  // namespace fnopt
