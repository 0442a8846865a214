#pragma once
// The rows a study's --resume keeps (compare, stability, repulsion-study): the earlier CSV's
// rows, keyed by the columns that name a run, so that a run already in the file is not run
// again, and rows that the new plan does not name (other methods, budgets, scenes) stay in the
// file (studies/sweep/sweep_rows.hpp puts them in order).
#include <map>
#include <set>
#include <string>
#include <vector>

namespace fnopt {

class ResumedRows {
 public:
  using Row = std::vector<std::string>;

  // Reads `path` when `resume` is set and the file exists; its header must be `columns`, else
  // Error("<path>: written by another version of <study>: cannot resume"). `key_columns` name
  // the columns that identify a run.
  ResumedRows(const std::string& path, const std::vector<std::string>& columns,
              const std::vector<std::string>& key_columns, bool resume, const std::string& study);

  // The key of a run, from its key columns' values in `key_columns` order.
  static std::string key(const std::vector<std::string>& values);
  // The earlier row of a run, or null.
  const Row* find(const std::string& key) const;
  // The earlier rows whose keys are not in `planned`, in the file's order.
  std::vector<Row> unplanned(const std::set<std::string>& planned) const;
  std::size_t size() const { return rows_.size(); }

 private:
  std::vector<Row> rows_;
  std::vector<std::string> keys_;  // of rows_
  std::map<std::string, std::size_t> index_;
};

}  // namespace fnopt
