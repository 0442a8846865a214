#pragma once
// The stability suite's cases (docs/design.md §8 "Stability"): each a change of a base scene.
#include <functional>
#include <string>
#include <vector>

#include <fnopt/scenes/scene.hpp>

namespace fnopt {

struct StabilityCase {
  std::string name;                          // "stretch-x100"
  std::string description;                   // one line for reports
  std::vector<std::string> fields;           // Scene fields it changes: "material.stretch", "material.shear",
                                             // "material.bend", "speed", "dt", "handles", "rows", "cols",
                                             // "frames", "obstacles"; empty for the baseline (the base scene itself)
  std::function<Scene(const Scene&)> apply;  // base scene -> the case's scene
};

// The suite, in report order: baseline; stretch x10, x100, x1000; soft (stretch and shear x0.1);
// bend x100, x0.01; speed x1.2, x1.5, x2, x4; dt 1/24, 1/240 (frames scaled to keep the base's
// simulated time); every other handle preset (the baseline is `corner`); 128^2 and 200^2 grids
// (on the first fifth and tenth of the base's frames: see the descriptions); contact: a sphere in
// the swing's way and a floor just below the cloth, alone, with the handles x4 faster, stretch x100
// and dt 1/24 (docs/design.md §14).
const std::vector<StabilityCase>& stability_cases();
std::vector<std::string> stability_case_names();
// The cases named in a comma-separated list, in its order, duplicates dropped; "" or "all":
// every case. Throws Error("cases", "unknown case 'x' (choose from: ...)").
std::vector<StabilityCase> select_stability_cases(const std::string& list);

}  // namespace fnopt
