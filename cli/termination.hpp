// How a pleat process ends when a signal stops it: Ctrl-C (SIGINT), a farm pre-empting a task (SIGTERM, or
// the SIGUSR1/SIGUSR2/SIGALRM some schedulers send first), a closed terminal (SIGHUP), SIGQUIT, a pipe whose
// reader went away (SIGPIPE: `pleat ... -o - | head`), a CPU time limit (SIGXCPU: `ulimit -t`, a batch
// system's h_cpu), timers (SIGVTALRM, SIGPROF), and every other signal whose default is to terminate; also
// Open MPI ending the surviving ranks of a failed job. The handler removes the temporary files of every
// output not yet committed (support/temporary_files.hpp; destructors do not run), says so in one line on
// stderr (under mpirun rank 0 alone) and exits with 128 + the signal (130 for SIGINT, 143 for SIGTERM, 152
// for SIGXCPU, ...). Outputs already renamed into place stay; a signal that comes while outputs are being
// renamed together (a CommitWindow) takes effect once they all are.
//
// Under a CPU time limit whose soft and hard values are the same (`ulimit -t N`), the kernel would end the
// process with SIGKILL, which no handler sees: pleat lowers its soft limit by one second, so that SIGXCPU
// comes first.
//
// SIGXFSZ that the kernel sends when a file grows past the file size limit (`ulimit -f`) does not stop the
// run: the write then fails with EFBIG and the run ends with exit status 1 naming the file ("file too
// large"). Sent by another process, SIGXFSZ stops the run like the others.
//
// Crashes (SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGSYS, SIGTRAP) remove the temporary files too, then
// go on to the action that was there before (the default: a core dump; under Open MPI, its backtrace).
#pragma once

namespace pleat::cli {

/// Installs the handlers, for every run, after World::init(). A signal ignored when pleat starts (nohup, a
/// background job of a non-interactive shell) stays ignored; a signal some library already handles keeps its
/// handler, except SIGINT, SIGTERM and SIGHUP.
void install_termination_handler();

}  // namespace pleat::cli
