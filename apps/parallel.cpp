#include "apps/parallel.h"

#include <cstdlib>
#include <initializer_list>
#include <stdexcept>

#include <mpi.h>

#ifdef PILELAB_WITH_CONTINUUM
#include "continuum/solve.h"
#endif

namespace pilelab::app {

bool launched_by_mpi() {
  // Open MPI, MPICH and Intel MPI (PMI), Slurm's srun (PMI and PMIx).
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}

struct MpiWorld::Session {
#ifdef PILELAB_WITH_CONTINUUM
  continuum::ParallelContext context;  // MPI and PETSc, as the solve stage needs them
#else
  Session() {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  }
  ~Session() { MPI_Finalize(); }
#endif
};

namespace {
std::unique_ptr<MpiWorld>& instance() {
  static std::unique_ptr<MpiWorld> world;
  return world;
}
bool stopped = false;
}  // namespace

MpiWorld& MpiWorld::get() {
  if (!instance()) {
    if (stopped) throw std::logic_error("MPI was stopped and cannot be started again in this process");
    instance().reset(new MpiWorld());
  }
  return *instance();
}

bool MpiWorld::started() { return instance() != nullptr; }

void MpiWorld::stop() {
  if (!instance()) return;
  instance().reset();
  stopped = true;
}

MpiWorld::MpiWorld() : session_(std::make_unique<Session>()) {
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm local;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &local);
  MPI_Comm_size(local, &local_size_);
  MPI_Comm_free(&local);
}

MpiWorld::~MpiWorld() = default;

void MpiWorld::barrier() const { MPI_Barrier(MPI_COMM_WORLD); }

bool MpiWorld::broadcast(bool value) const {
  int v = value ? 1 : 0;
  MPI_Bcast(&v, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return v != 0;
}

bool MpiWorld::any(bool failed) const {
  int mine = failed ? 1 : 0, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return all != 0;
}

struct MpiWorld::SharedCounter::Window {
  MPI_Win window = MPI_WIN_NULL;
  long* value = nullptr;  // on rank 0
};

MpiWorld::SharedCounter::SharedCounter(const MpiWorld& world) : window_(std::make_unique<Window>()) {
  const MPI_Aint bytes = world.root() ? static_cast<MPI_Aint>(sizeof(long)) : 0;
  MPI_Win_allocate(bytes, sizeof(long), MPI_INFO_NULL, MPI_COMM_WORLD, &window_->value, &window_->window);
  if (world.root()) *window_->value = 0;
  MPI_Win_fence(0, window_->window);  // rank 0's zero is in place before anyone counts
}

MpiWorld::SharedCounter::~SharedCounter() {
  MPI_Win_fence(0, window_->window);
  MPI_Win_free(&window_->window);
}

long MpiWorld::SharedCounter::next() {
  const long one = 1;
  long previous = 0;
  MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, window_->window);
  MPI_Fetch_and_op(&one, &previous, MPI_LONG, 0, 0, MPI_SUM, window_->window);
  MPI_Win_unlock(0, window_->window);
  return previous;
}

}  // namespace pilelab::app
