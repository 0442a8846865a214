#include "cloth/material.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include "util/error.hpp"

namespace fnopt {
namespace {

void require_positive(double value, const char* field) {
  require(std::isfinite(value) && value > 0.0, std::string("material.") + field,
          "must be a positive finite number");
}

void require_non_negative(double value, const char* field) {
  require(std::isfinite(value) && value >= 0.0, std::string("material.") + field,
          "must be a non-negative finite number");
}

// A material file: "key = value" lines (stretch, shear, bend, density, damping,
// repulsion_stiffness, repulsion_range), '#' comments.
Material load_material_file(const std::string& path) {
  std::ifstream in(path);
  require(static_cast<bool>(in), "material", "unknown preset or unreadable file '" + path + "'");
  Material m;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    line = line.substr(0, line.find('#'));
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const auto eq = line.find('=');
    const std::string where = path + ":" + std::to_string(number);
    require(eq != std::string::npos, where, "expected 'key = value'");
    std::istringstream key_in(line.substr(0, eq)), value_in(line.substr(eq + 1));
    std::string key, rest;
    double value = 0.0;
    key_in >> key;
    require(static_cast<bool>(value_in >> value) && !(value_in >> rest), where + ": " + key,
            "expected a number");
    if (key == "stretch") m.stretch = value;
    else if (key == "shear") m.shear = value;
    else if (key == "bend") m.bend = value;
    else if (key == "density") m.density = value;
    else if (key == "damping") m.damping = value;
    else if (key == "repulsion_stiffness") m.repulsion_stiffness = value;
    else if (key == "repulsion_range") m.repulsion_range = value;
    else throw Error(where + ": unknown material key '" + key + "'");
  }
  m.validate();
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
