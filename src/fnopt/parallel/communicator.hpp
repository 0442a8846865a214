#pragma once
// The processes of one run (docs/design.md §12). `fnopt` started by mpirun or srun is one rank of
// MPI_COMM_WORLD; started alone it is a single process and never touches MPI, so a plain run
// costs nothing and needs no launcher. Every operation here is collective over the
// communicator's ranks unless it says otherwise; with one rank each is a no-op or a copy. Built
// without MPI (FNOPT_WITH_MPI=OFF), every run is a single process.
#include <cstddef>
#include <string>
#include <vector>

namespace fnopt {

class Communicator {
 public:
  // MPI_COMM_WORLD when this process was started by an MPI launcher (MpiSession initialised
  // MPI), else this process alone.
  static const Communicator& world();
  // This process alone, whatever the launcher: the one-process reference of a distributed run.
  static const Communicator& self();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool is_root() const { return rank_ == 0; }

  // Sums `data` over the ranks, in place (MPI_Allreduce).
  void sum(float* data, std::size_t count) const;
  void sum(double* data, std::size_t count) const;
  double sum(double value) const;
  int sum(int value) const;
  // True on every rank if `flag` is true on any.
  bool any(bool flag) const;
  // Rank 0's `text` on every rank.
  void broadcast(std::string& text) const;
  // Every rank's `text`, in rank order, at rank 0 (empty elsewhere).
  std::vector<std::string> gather(const std::string& text) const;
  void barrier() const;

  // Point to point, not collective: rank != 0 sends a message to rank 0, which takes the
  // messages that have arrived without waiting (take_arrived) or waits for one (wait_for).
  struct Message {
    int source = 0;
    std::string text;
  };
  void send_to_root(const std::string& text) const;
  bool take_arrived(Message& message) const;
  Message wait_for() const;

  // Stops every rank of the run with `code` (MPI_Abort); one process simply exits.
  [[noreturn]] void abort(int code) const;

 private:
  // More than one rank only in MPI_COMM_WORLD of a run that initialised MPI.
  Communicator(int rank, int size) : rank_(rank), size_(size) {}
  int rank_, size_;
};

// MPI's lifetime in main(): initialises MPI when an MPI launcher started the process (OpenMPI's
// mpirun, or srun through PMI/PMIx; FNOPT_MPI=1 forces it) and finalises it at the end.
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  static bool active();  // MPI was initialised here

 private:
  bool initialised_ = false;
};

}  // namespace fnopt
