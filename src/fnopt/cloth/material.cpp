#include <fnopt/cloth/material.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// Errors name the field as the user sets it: the flag (--stretch), the scene-file key and the
// material-file key share the name.
void require_positive(double value, const char* field) {
  require(std::isfinite(value) && value > 0.0, field, "must be a positive finite number");
}

void require_non_negative(double value, const char* field) {
  require(std::isfinite(value) && value >= 0.0, field, "must be a non-negative finite number");
}

// A material file: "key = value" lines (stretch, shear, bend, density, damping,
// repulsion_stiffness, repulsion_range), '#' comments; each key at most once.
Material load_material_file(const std::string& path) {
  std::error_code ignored;
  require(!std::filesystem::is_directory(path, ignored), "material",
          "'" + path + "' is a directory, not a preset or material file");
  std::ifstream in(path);
  require(static_cast<bool>(in), "material", "unknown preset or unreadable file '" + path + "' (presets: default)");
  Material m;
  const std::map<std::string, double Material::*> fields = {{"stretch", &Material::stretch},
                                                            {"shear", &Material::shear},
                                                            {"bend", &Material::bend},
                                                            {"density", &Material::density},
                                                            {"damping", &Material::damping},
                                                            {"repulsion_stiffness", &Material::repulsion_stiffness},
                                                            {"repulsion_range", &Material::repulsion_range}};
  std::map<std::string, int> seen;  // key -> line
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    line = line.substr(0, line.find('#'));
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = path + ":" + std::to_string(number);
    require(std::all_of(line.begin(), line.end(), [](unsigned char c) { return c >= 32 || c == '\t' || c == '\r'; }),
            where, "not a text material file");
    const auto eq = line.find('=');
    require(eq != std::string::npos, where, "expected 'key = value'");
    std::istringstream key_in(line.substr(0, eq)), value_in(line.substr(eq + 1));
    std::string key, rest;
    key_in >> key;
    const auto field = fields.find(key);
    require(
        field != fields.end(), where + ": " + key,
        "unknown material key (valid: stretch, shear, bend, density, damping, repulsion_stiffness, repulsion_range)");
    const auto [first, fresh] = seen.emplace(key, number);
    require(fresh, where + ": " + key, "given twice (first on line " + std::to_string(first->second) + ")");
    double value = 0.0;
    require(static_cast<bool>(value_in >> value) && !(value_in >> rest), where + ": " + key, "expected a number");
    m.*(field->second) = value;
  }
  try {
    m.validate();
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
  return m;
}

}  // namespace

void Material::validate() const {
  require_positive(stretch, "stretch");
  require_non_negative(shear, "shear");
  require_non_negative(bend, "bend");
  require_positive(density, "density");
  require_non_negative(damping, "damping");
  require_positive(repulsion_stiffness, "repulsion_stiffness");
  require_positive(repulsion_range, "repulsion_range");
}

Material material_preset(const std::string& name) {
  if (name == "default") return Material{};
  return load_material_file(name);
}

}  // namespace fnopt
