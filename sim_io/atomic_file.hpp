// Atomic output: a file is written to a temporary sibling of its target and renamed into place only when the
// whole content was written and flushed, so a failed run never leaves a partial output.
//
// The target is the path with its symbolic links followed: a link is written through (the link stays a link
// and the file it names is replaced), the temporary goes beside that file, so the rename stays within one
// directory and is atomic on POSIX file systems. Only a regular file (or nothing) is ever replaced: a path
// that is a directory, FIFO, socket or device, or whose links loop, is refused (OutputRefused). If the writer
// throws before commit(), or any I/O step fails, the temporary file is removed and the target is left as it
// was.
//
// The path "-" names standard output: the bytes are streamed to it as they come, with no atomicity (a failed
// run has already written part of them).
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <ostream>
#include <streambuf>
#include <string>

#include "static_core/input_error.hpp"

namespace pleat {

/// The path that names standard output.
inline constexpr const char* kStandardOutput = "-";

/// An output path that pleat will not replace: names the path and what it is. A usage error (the CLI exits
/// 2).
class OutputRefused : public InputError {
 public:
  OutputRefused(const std::filesystem::path& path, const std::string& what)
      : InputError(path.string(), "", what) {}
};

/// The regular file writing `path` replaces or creates: `path` with its symbolic links followed (a relative
/// link is read from its own directory; a dangling link names the file to create). "-" is returned as it is.
/// Throws OutputRefused when that file exists and is not a regular file, or the links loop. Call it on every
/// output before the work starts, so a bad target is refused before anything is computed. Costs an lstat per
/// link.
std::filesystem::path resolve_output_target(const std::filesystem::path& path);

/// A streaming atomic output file: write to stream(), then commit(). Destroyed without commit(), it
/// removes its temporary file. Throws OutputRefused for a target resolve_output_target() refuses, and
/// std::runtime_error naming the path on any I/O failure.
class AtomicFile {
 public:
  /// Resolves the target and creates the temporary file beside it (its directory must exist).
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return m_out; }
  /// The path as given (for messages).
  const std::filesystem::path& path() const { return m_path; }
  /// Flushes, closes and renames the temporary file onto the target (checked again: still not anything but a
  /// regular file). On standard output: flushes. Called once.
  void commit();

 private:
  std::filesystem::path m_path;
  std::filesystem::path m_target;     // m_path with symbolic links followed
  std::filesystem::path m_temporary;  // empty on standard output
  std::unique_ptr<std::streambuf> m_buffer;
  std::ostream m_out;
  bool m_committed = false;
  int m_slot = -1;  // in the list remove_uncommitted_files() empties
};

/// Writes `path` atomically with the bytes `write` puts on the (binary) stream; rethrows what `write` throws.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write);

/// Convenience: writes a whole byte/text buffer atomically.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

/// Removes the temporary file of every AtomicFile not yet committed (or destroyed). Async-signal-safe (only
/// unlink): for a termination signal handler, where destructors do not run (cli/termination.hpp).
void remove_uncommitted_files() noexcept;

}  // namespace pleat
