#pragma once
// The MPI world of one `pilelab` process: started once (with PETSc, where the continuum module
// is built, since the solve stage needs both), kept for the rest of the process, and finalised
// at exit. Under mpirun it starts at once; otherwise only when a stage needs it, so that a
// serial run with `-P N` can still fork its member processes first (MPI forbids forking after
// it has started on some transports).
#include <memory>

namespace pilelab::app {

/// True if this process was started by mpirun, srun or another MPI launcher (its environment
/// says so), whether or not MPI has been started yet.
bool launched_by_mpi();

class MpiWorld {
 public:
  /// The process's world, started on first use.
  static MpiWorld& get();
  static bool started();
  /// Finalises MPI (and PETSc) if it was started; the process cannot start it again. Called by
  /// the command that used it, before it returns (not from a static destructor, which would run
  /// after the libraries' own).
  static void stop();
  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  /// Ranks sharing this machine (for the default thread count per rank).
  int ranks_on_this_machine() const { return local_size_; }
  void barrier() const;
  /// Rank 0's value on every rank.
  bool broadcast(bool value) const;
  /// An error on any rank ends the collective step on all: true if some rank failed.
  bool any(bool failed) const;

  /// A counter shared by all ranks: each call on any rank returns the next integer, 0, 1, 2, ...,
  /// so that ranks take the next piece of work when they are free (MPI one-sided fetch-and-add).
  class SharedCounter {
   public:
    explicit SharedCounter(const MpiWorld& world);
    ~SharedCounter();
    long next();

   private:
    struct Window;
    std::unique_ptr<Window> window_;
  };

  MpiWorld(const MpiWorld&) = delete;
  MpiWorld& operator=(const MpiWorld&) = delete;
  ~MpiWorld();

 private:
  MpiWorld();
  struct Session;
  std::unique_ptr<Session> session_;
  int rank_ = 0, size_ = 1, local_size_ = 1;
};

}  // namespace pilelab::app
