#include <fnopt/parallel/communicator.hpp>

#include <cstdlib>
#include <cstring>
#include <limits>

#if FNOPT_WITH_MPI
#include <mpi.h>
#endif

#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

bool g_mpi_active = false;

bool started_by_launcher() {
  for (const char* name : {"FNOPT_MPI", "OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (const char* value = std::getenv(name); value && *value && std::strcmp(value, "0") != 0) return true;
  return false;
}

}  // namespace

bool MpiSession::active() { return g_mpi_active; }

const Communicator& Communicator::self() {
  static const Communicator self(0, 1);
  return self;
}

double Communicator::sum(double value) const {
  sum(&value, 1);
  return value;
}

bool Communicator::any(bool flag) const { return sum(flag ? 1 : 0) > 0; }

#if FNOPT_WITH_MPI
MpiSession::MpiSession(int& argc, char**& argv) {
  if (!started_by_launcher()) return;
  int provided = 0;
  // Funneled: only the main thread calls MPI; OpenMP and LibTorch threads compute inside a rank.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  // Errors come back as codes (and are turned into Error), not MPI's default abort.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  initialised_ = g_mpi_active = true;
}

MpiSession::~MpiSession() {
  if (initialised_) MPI_Finalize();
}

const Communicator& Communicator::world() {
  static const Communicator world = [] {
    if (!g_mpi_active) return Communicator(0, 1);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    return Communicator(rank, size);
  }();
  return world;
}

namespace {
int count_of(std::size_t count) {
  if (count > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw Error("mpi", "a message of " + std::to_string(count) + " elements is larger than MPI's int counts allow");
  return static_cast<int>(count);
}

constexpr int kRootMessageTag = 7301;

void check(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw Error(std::string("mpi: ") + what + " failed (" + std::string(text, length) + ")");
}
}  // namespace

void Communicator::sum(float* data, std::size_t count) const {
  if (size_ > 1)
    check(MPI_Allreduce(MPI_IN_PLACE, data, count_of(count), MPI_FLOAT, MPI_SUM, MPI_COMM_WORLD), "Allreduce");
}

void Communicator::sum(double* data, std::size_t count) const {
  if (size_ > 1)
    check(MPI_Allreduce(MPI_IN_PLACE, data, count_of(count), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD), "Allreduce");
}

int Communicator::sum(int value) const {
  if (size_ > 1) check(MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD), "Allreduce");
  return value;
}

void Communicator::broadcast(std::string& text) const {
  if (size_ == 1) return;
  unsigned long long length = text.size();
  check(MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD), "Bcast");
  text.resize(length);
  check(MPI_Bcast(text.data(), count_of(length), MPI_CHAR, 0, MPI_COMM_WORLD), "Bcast");
}

std::vector<std::string> Communicator::gather(const std::string& text) const {
  if (size_ == 1) return {text};
  const int length = count_of(text.size());
  std::vector<int> lengths(is_root() ? size_ : 0), offsets(is_root() ? size_ : 0);
  check(MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "Gather");
  std::string all;
  if (is_root()) {
    std::size_t total = 0;
    for (int r = 0; r < size_; ++r) offsets[r] = count_of(total), total += lengths[r];
    all.resize(total);
  }
  check(MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
                    MPI_COMM_WORLD),
        "Gatherv");
  std::vector<std::string> texts;
  for (int r = 0; r < static_cast<int>(lengths.size()); ++r) texts.push_back(all.substr(offsets[r], lengths[r]));
  return texts;
}

void Communicator::barrier() const {
  if (size_ > 1) check(MPI_Barrier(MPI_COMM_WORLD), "Barrier");
}

void Communicator::send_to_root(const std::string& text) const {
  if (size_ == 1 || is_root()) throw Error("mpi", "send_to_root from rank 0 or a single process");
  check(MPI_Send(text.data(), count_of(text.size()), MPI_CHAR, 0, kRootMessageTag, MPI_COMM_WORLD), "Send");
}

namespace {
Communicator::Message receive(const MPI_Status& status) {
  int length = 0;
  MPI_Get_count(&status, MPI_CHAR, &length);
  Communicator::Message message;
  message.source = status.MPI_SOURCE;
  message.text.resize(length);
  check(MPI_Recv(message.text.data(), length, MPI_CHAR, status.MPI_SOURCE, kRootMessageTag, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE),
        "Recv");
  return message;
}
}  // namespace

bool Communicator::take_arrived(Message& message) const {
  if (size_ == 1) return false;
  int arrived = 0;
  MPI_Status status;
  check(MPI_Iprobe(MPI_ANY_SOURCE, kRootMessageTag, MPI_COMM_WORLD, &arrived, &status), "Iprobe");
  if (!arrived) return false;
  message = receive(status);
  return true;
}

Communicator::Message Communicator::wait_for() const {
  if (size_ == 1) throw Error("mpi", "wait_for in a single process");
  MPI_Status status;
  check(MPI_Probe(MPI_ANY_SOURCE, kRootMessageTag, MPI_COMM_WORLD, &status), "Probe");
  return receive(status);
}

void Communicator::abort(int code) const {
  if (g_mpi_active) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

#else  // built without MPI: every run is one process

MpiSession::MpiSession(int&, char**&) {
  if (started_by_launcher())
    throw Error("mpi", "this fnopt was built without MPI (FNOPT_WITH_MPI=OFF); run it as one process");
}

MpiSession::~MpiSession() = default;

const Communicator& Communicator::world() { return self(); }

void Communicator::sum(float*, std::size_t) const {}
void Communicator::sum(double*, std::size_t) const {}
int Communicator::sum(int value) const { return value; }
void Communicator::broadcast(std::string&) const {}
std::vector<std::string> Communicator::gather(const std::string& text) const { return {text}; }
void Communicator::barrier() const {}

void Communicator::send_to_root(const std::string&) const {
  throw Error("mpi", "send_to_root from rank 0 or a single process");
}

bool Communicator::take_arrived(Message&) const { return false; }

Communicator::Message Communicator::wait_for() const { throw Error("mpi", "wait_for in a single process"); }

void Communicator::abort(int code) const { std::exit(code); }

#endif

}  // namespace fnopt
