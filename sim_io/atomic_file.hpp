// Atomic output: a file is written to a temporary sibling in the same directory and renamed into place
// only when the whole content was written and flushed, so a failed run never leaves a partial output.
//
// The rename is atomic on POSIX file systems when source and target share a directory. If the writer
// throws before commit(), or any I/O step fails, the temporary file is removed and the target is left as
// it was (an existing file is not touched).
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <ostream>
#include <string>

namespace pleat {

/// A streaming atomic output file: write to stream(), then commit(). Destroyed without commit(), it
/// removes its temporary file. Throws std::runtime_error naming the path on any I/O failure.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path);  ///< creates the temporary file (parent must exist)
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return m_out; }
  const std::filesystem::path& path() const { return m_path; }
  /// Flushes, closes and renames the temporary file into place. Called once.
  void commit();

 private:
  std::filesystem::path m_path;
  std::filesystem::path m_temporary;
  std::ofstream m_out;
  bool m_committed = false;
  int m_slot = -1;  // in the list remove_uncommitted_files() empties
};

/// Writes `path` atomically with the bytes `write` puts on the (binary) stream; rethrows what `write` throws.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write);

/// Convenience: writes a whole byte/text buffer atomically.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

/// Removes the temporary file of every AtomicFile not yet committed (or destroyed). Async-signal-safe (only
/// unlink): for a termination signal handler, where destructors do not run (cli/distributed.cpp).
void remove_uncommitted_files() noexcept;

}  // namespace pleat
