#pragma once
// The rows of a sweep study's table (compare.csv, stability.csv, repulsion.csv) in the order one
// process writes them, however the ranks finished them: first the rows of an earlier run that
// this plan does not name (resuming with a subset never drops finished work), then every planned
// row, kept from the earlier run (--resume) or finished now, in plan order.
#include <cstddef>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <fnopt/studies/sweep/resumed_rows.hpp>

namespace fnopt {

template <class Result>
class SweepRows {
 public:
  using Row = ResumedRows::Row;

  explicit SweepRows(const ResumedRows& resumed) : resumed_(resumed) {}

  // A planned row, named by its key columns' values (ResumedRows::key); returns its slot.
  std::size_t plan(const std::vector<std::string>& key_values) {
    keys_.push_back(ResumedRows::key(key_values));
    return keys_.size() - 1;
  }
  std::size_t planned() const { return keys_.size(); }
  // The earlier row of a planned slot, or null.
  const Row* resumed(std::size_t slot) const { return resumed_.find(keys_.at(slot)); }
  void finish(std::size_t slot, Result result) { finished_[slot] = std::move(result); }
  const Result* finished(std::size_t slot) const {
    const auto it = finished_.find(slot);
    return it == finished_.end() ? nullptr : &it->second;
  }
  // The earlier rows that no planned slot names, in the file's order.
  std::vector<Row> unplanned() const { return resumed_.unplanned(std::set<std::string>(keys_.begin(), keys_.end())); }

  // Visits the planned rows in plan order: earlier(slot, row) for a resumed one, now(slot,
  // result) for one finished now; a row neither resumed nor finished yet is skipped.
  template <class Earlier, class Now>
  void visit(Earlier&& earlier, Now&& now) const {
    for (std::size_t slot = 0; slot < keys_.size(); ++slot) {
      if (const Row* row = resumed(slot))
        earlier(slot, *row);
      else if (const Result* result = finished(slot))
        now(slot, *result);
    }
  }

 private:
  const ResumedRows& resumed_;
  std::vector<std::string> keys_;  // of the slots
  std::map<std::size_t, Result> finished_;
};

}  // namespace fnopt
