#pragma once
// compare.svg: error against run time, one line per method through its budgets.
#include <string>
#include <vector>

#include <fnopt/io/svg_plot.hpp>
#include <fnopt/studies/compare/compare_run_result.hpp>

namespace fnopt {

// The error-time figure: one row of panels per resolution, one line per method.
PlotFigure make_compare_plot(const std::vector<RunResult>& results, const std::vector<std::string>& methods,
                             const std::vector<std::string>& resolutions, const std::vector<std::string>& motions,
                             int threads, const std::vector<std::string>& notes);

}  // namespace fnopt
