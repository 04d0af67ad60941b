// Errors every rank of a job learns about together (bad input), reported once by rank 0 with the exit status
// a single process would give. An error only one rank meets (or a rank killed) is not agreed on: it aborts
// the whole job (World::abort, or Open MPI's own kill); rank 0 then removes its temporary output files from
// its termination handler (cli/termination.hpp), so no partial output is left.
#pragma once

#include <exception>
#include <functional>
#include <stdexcept>
#include <string>

namespace pleat::cli {

/// An error all ranks met or learnt of together (through agree()): rank 0 prints it, every rank exits with
/// `code` (2: bad input, 1: anything else), as a single process would.
class JobError : public std::runtime_error {
 public:
  JobError(const std::string& what, int code) : std::runtime_error(what), m_code(code) {}
  int code() const { return m_code; }

 private:
  int m_code;
};

/// Collective: every rank passes what it threw (or null). If any rank failed, every rank throws the JobError
/// of the lowest failing rank (ranks hold contiguous frame ranges in order, so that is the error of the
/// lowest frame, the one a single process meets first). With one rank, rethrows `error` as it is.
void agree(std::exception_ptr error);

/// Runs `step` on rank 0 alone, for a subcommand that does not split its work (info, generate, compare, view)
/// launched by `mpirun -np N`: the other ranks wait without spinning (they look for rank 0's word every 20
/// ms) and every rank ends with rank 0's exit status; rank 0's error is reported once (JobError). With one
/// rank, runs `step`.
void on_rank_zero_alone(const std::function<void()>& step);

/// Runs `step` on every rank and agree()s on what it threw: for steps every rank takes together.
template <class Step>
void together(Step&& step) {
  std::exception_ptr error;
  try {
    step();
  } catch (const JobError&) {
    throw;
  } catch (...) {
    error = std::current_exception();
  }
  agree(error);
}

}  // namespace pleat::cli
