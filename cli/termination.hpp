// How a pleat process ends when stopped by SIGINT, SIGTERM or SIGHUP (Ctrl-C, a farm pre-empting a task, a
// closed terminal; also Open MPI ending the surviving ranks of a failed job): it removes the temporary files
// of every output not yet committed (sim_io/atomic_file.hpp; destructors do not run), says so in one line on
// stderr (under mpirun rank 0 alone) and exits with 128 + the signal: 130, 143, 129. Outputs already renamed
// into place stay.
#pragma once

namespace pleat::cli {

/// Installs the handler, for every run, after World::init(). A signal ignored when pleat starts (nohup, a
/// background job of a non-interactive shell) stays ignored.
void install_termination_handler();

}  // namespace pleat::cli
