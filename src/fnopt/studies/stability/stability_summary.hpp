#pragma once
// How the stability suite's rows read: the table on a terminal, "what fails where", and
// stability.svg's figure.
#include <string>
#include <vector>

#include <fnopt/io/svg_plot.hpp>
#include <fnopt/studies/stability/stability_cases.hpp>
#include <fnopt/studies/stability/stability_run.hpp>

namespace fnopt {

// The table for a terminal: aligned columns, strain in %, e_3D x 10^2.
std::string stability_console_table(const std::vector<StabilityRow>& rows);
// "What fails where": one line per method (finished / diverged / errors, with the cases and
// steps), Newton's unconverged steps, energy blow-ups among finished runs, the largest e_3D.
std::vector<std::string> stability_summary(const std::vector<StabilityRow>& rows,
                                           const std::vector<std::string>& methods);
// Max strain (log) and energy growth (log) per case (x: the case number, 1 = the first case),
// one series per method; diverged and failed runs marked.
PlotFigure stability_plot(const std::vector<StabilityRow>& rows, const std::vector<StabilityCase>& cases,
                          const std::vector<std::string>& methods, const std::vector<std::string>& notes);

}  // namespace fnopt
