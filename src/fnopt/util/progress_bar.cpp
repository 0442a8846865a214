#include <fnopt/util/progress_bar.hpp>

#include <unistd.h>

#include <cstdio>

namespace fnopt {

std::string format_duration(double seconds) {
  const long s = static_cast<long>(seconds + 0.5);
  char text[32];
  if (s >= 3600)
    std::snprintf(text, sizeof text, "%ldh%02ldm", s / 3600, (s % 3600) / 60);
  else if (s >= 60)
    std::snprintf(text, sizeof text, "%ldm%02lds", s / 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%lds", s);
  return text;
}

ProgressBar::ProgressBar(std::string label, int total, int first)
    : label_(std::move(label)),
      total_(total),
      first_(first),
      terminal_(::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()) {}

void ProgressBar::update(int done, const std::string& status) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fraction = total_ > 0 ? static_cast<double>(done) / total_ : 1.0;
  const double eta = done > first_ ? elapsed * (total_ - done) / (done - first_) : 0.0;
  if (terminal_) {
    constexpr int width = 30;
    const int filled = static_cast<int>(fraction * width);
    std::fprintf(stderr, "\r%s [%s%s] %d/%d %3d%% %s, ETA %s %s\033[K", label_.c_str(),
                 std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), done, total_,
                 static_cast<int>(100 * fraction), format_duration(elapsed).c_str(), format_duration(eta).c_str(),
                 status.c_str());
  } else {
    const int decile = static_cast<int>(10 * fraction);
    if (decile == last_decile_) return;
    last_decile_ = decile;
    std::fprintf(stderr, "%s %d/%d %3d%% elapsed %s ETA %s %s\n", label_.c_str(), done, total_,
                 static_cast<int>(100 * fraction), format_duration(elapsed).c_str(), format_duration(eta).c_str(),
                 status.c_str());
  }
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (terminal_ && !finished_) std::fprintf(stderr, "\n");
  finished_ = true;
}

}  // namespace fnopt
