// Atomic output: a file is written to a temporary sibling of its target and renamed into place only when the
// whole content was written and flushed, so a failed run never leaves a partial output.
//
// The target is the path with its symbolic links followed: a link is written through (the link stays a link
// and the file it names is replaced), the temporary goes beside that file, so the rename stays within one
// directory and is atomic on POSIX file systems. Only a regular file (or nothing) is ever replaced: a path
// that is a directory, FIFO, socket or device, or whose links loop, is refused (OutputRefused). If the writer
// throws before commit(), or any I/O step fails, the temporary file is removed and the target is left as it
// was. A failed write is reported with its reason and the file ("v.csv: cannot write: no space left on
// device"). Temporaries are named and listed as support/temporary_files.hpp says, so a termination signal
// removes them and a later run removes those of a process that died.
//
// Several outputs replace their targets together: each is written and close()d first (a failure there leaves
// every target as it was), then all are commit()ted inside one CommitWindow (support/temporary_files.hpp).
// StagedFiles does the same for a directory of many files (renders).
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
#include <string_view>
#include <vector>

#include "support/input_error.hpp"
#include "support/temporary_files.hpp"

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

/// What a failed write of errno `error` means, for messages: "no space left on device", "file too large
/// (over the file size limit, ulimit -f)", ... (strerror's text for the rest; "I/O error" for 0).
std::string write_failure_reason(int error);

/// A streaming atomic output file: write to stream(), then close() and commit(), or commit() alone. Destroyed
/// without commit(), it removes its temporary file. Throws OutputRefused for a target
/// resolve_output_target() refuses, and std::runtime_error naming the path and the reason on any I/O failure.
class AtomicFile {
 public:
  /// Resolves the target and creates the temporary file beside it (its directory must exist).
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// The file's stream (seekable, except on standard output).
  std::ostream& stream() { return m_out; }
  /// The path as given (for messages).
  const std::filesystem::path& path() const { return m_path; }
  /// Throws the error of a failed write to stream() so far, naming the path and the reason (writers call it
  /// per frame, so that a full disk ends the run at once).
  void check() const;
  /// Flushes and closes the temporary file (on standard output: flushes); throws on I/O failure. After it
  /// only commit() is left, which can then fail only if the target changed meanwhile. Idempotent.
  void close();
  /// close(), then renames the temporary file onto the target (checked again: still not anything but a
  /// regular file). Called once.
  void commit();

 private:
  std::filesystem::path m_path;
  std::filesystem::path m_target;     // m_path with symbolic links followed
  std::filesystem::path m_temporary;  // empty on standard output
  std::unique_ptr<std::streambuf> m_buffer;
  std::ostream m_out;
  bool m_closed = false;
  bool m_committed = false;
  int m_slot = -1;  // in the list remove_uncommitted_files() empties
};

/// Files that appear in a directory together, or not at all (a render's images): add() writes each into a
/// hidden staging directory inside it (`.pleat-staged.tmp.HOST.PID.N/`, a listed temporary), commit() moves
/// every one onto its name, replacing the older file of that name (a symbolic link there is written through,
/// as AtomicFile does); destroyed without commit(), the staging directory and everything in it go.
class StagedFiles {
 public:
  /// Creates `directory` if missing, and the staging directory in it.
  explicit StagedFiles(std::filesystem::path directory);
  ~StagedFiles();
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;

  /// Writes `bytes` as the file `name` to appear at commit(). Throws OutputRefused when directory/name is not
  /// a file pleat may replace, std::runtime_error naming it and the reason on I/O failure.
  void add(const std::string& name, std::string_view bytes);
  /// Moves every file added into place and removes the staging directory. Called once, inside the
  /// CommitWindow of the run's other outputs.
  void commit();
  const std::filesystem::path& directory() const { return m_directory; }

 private:
  std::filesystem::path m_directory;
  std::filesystem::path m_staging;
  std::vector<std::string> m_names;
  int m_slot = -1;
  bool m_committed = false;
};

/// Writes `path` atomically with the bytes `write` puts on the (binary) stream; rethrows what `write` throws.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write);

/// Convenience: writes a whole byte/text buffer atomically.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

}  // namespace pleat
