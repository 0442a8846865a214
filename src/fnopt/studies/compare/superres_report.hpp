#pragma once
// compare's zero-shot super-resolution section (docs/design.md §8): the learned optimizer run
// unchanged on each grid against the same optimizer solving coarse and interpolating, as tables
// in report.md and as superres.svg (error and ms/frame against the vertex count).
#include <vector>

#include <fnopt/io/markdown_report.hpp>
#include <fnopt/studies/compare/compare_report.hpp>

namespace fnopt {

// Adds the section to `md` and writes DIR/superres.svg, where the results hold fnopt and an
// interpolation method; nothing otherwise.
void write_superres_section(MarkdownReport& md, const CompareReport& report, const std::vector<RunResult>& results);

}  // namespace fnopt
