#pragma once
// A progress bar with ETA on stderr for long work. On a terminal it redraws one line; in a log
// (not a terminal) it prints a line at every 10 % so CI logs stay short.
#include <chrono>
#include <string>

namespace fnopt {

class ProgressBar {
 public:
  // `first` units were done before this bar started (a resumed run): they count for the
  // fraction shown but not for the rate behind the ETA.
  ProgressBar(std::string label, int total, int first = 0);
  // Reports `done` of `total` units, with a short status text (e.g. the running loss).
  void update(int done, const std::string& status = {});
  // Ends the line (terminal) so that later output starts on a fresh line.
  void finish();

 private:
  std::string label_;
  int total_;
  int first_;
  bool terminal_;
  int last_decile_ = -1;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
};

// "1h02m", "3m05s", "12s"
std::string format_duration(double seconds);

}  // namespace fnopt
