// The temporary files and directories of outputs being written (support/atomic_file.hpp): their names, a
// process-wide list of them that a termination signal handler can empty (cli/termination.hpp), the clean-up
// of those left behind by processes that died without emptying theirs (SIGKILL, an out-of-memory kill, a
// lost farm node), and the commit window that holds termination back while several outputs are renamed
// into place together.
//
// A temporary is named `.NAME.tmp.HOST.PID.N` beside its target NAME (HOST: this machine's name, PID: the
// process that made it, N: a per-process counter). So a later run can tell whose it is: one of this machine
// whose process no longer exists is left over and is removed; any other (another machine's, on a shared file
// system, or a live process's) is never touched. A PID reused by an unrelated live process keeps the
// temporary (it is never wrongly removed, only kept longer).
//
// Thread safety: every function may be called from any thread; remove_uncommitted_files() and
// hold_back_termination() are async-signal-safe.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace pleat {

/// `directory/.NAME.tmp.HOST.PID.N` for a temporary of target `name` made by this process, N unique in it.
std::filesystem::path temporary_path(const std::filesystem::path& directory, const std::string& name);

/// Lists `path` for remove_uncommitted_files(): a file, or (`directory`) a directory holding files only. Call
/// it before creating the file or directory, so that a signal at any moment finds everything this process
/// made. Returns the slot to unlist it with; -1 when the path does not fit the list (4095 bytes), which then
/// simply does not cover it. Allocates only when every slot so far is taken.
int list_temporary(const std::filesystem::path& path, bool directory = false);
/// Takes a slot off the list (after the temporary was renamed into place or removed); -1 is ignored.
void unlist_temporary(int slot) noexcept;

/// Removes every listed temporary (a listed directory with the files in it). Async-signal-safe (unlink,
/// open, getdents64, unlinkat, rmdir): for a termination signal handler, where destructors do not run.
void remove_uncommitted_files() noexcept;

/// Removes from `directory` the temporaries that processes of this machine which no longer exist left
/// behind: those of target `name`, or with an empty `name` those of any target (a directory pleat writes
/// into: renders, checkpoints). Returns how many it removed. Never throws: what it cannot list or remove
/// stays. Cost: one listing of `directory` and one kill(pid, 0) per candidate.
std::size_t remove_stale_temporaries(const std::filesystem::path& directory, const std::string& name = {});

/// While a CommitWindow is open, a termination signal is held back (hold_back_termination()) and acted on
/// when the window closes: outputs renamed into place inside one window all appear, or (stopped before it
/// opened) none does. One window at a time, on the thread that renames.
class CommitWindow {
 public:
  CommitWindow();
  /// Closes the window; a signal held meanwhile is passed to the handler given to on_held_termination().
  ~CommitWindow();
  CommitWindow(const CommitWindow&) = delete;
  CommitWindow& operator=(const CommitWindow&) = delete;
};

/// For a termination signal handler: true when a CommitWindow is open, `signal` is then recorded (the
/// handler should return and let the renames finish); false otherwise. Async-signal-safe.
bool hold_back_termination(int signal) noexcept;
/// What a held signal does when its window closes (the termination handler; it does not return).
void on_held_termination(void (*handler)(int)) noexcept;

}  // namespace pleat
