// Atomic output: a file is written to a temporary sibling in the same directory and renamed into place
// only when the whole content was written and flushed, so a failed run never leaves a partial output.
//
// The rename is atomic on POSIX file systems when source and target share a directory. If the writer
// callback throws, or any I/O step fails, the temporary file is removed and the target is left as it was.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace pleat {

/// Writes `path` atomically with the bytes `write` puts on the (binary) stream. Rethrows whatever `write`
/// throws; throws std::runtime_error naming the path when the temporary file cannot be created, written or
/// renamed. The parent directory must exist.
void write_file_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

/// Convenience: writes a whole byte/text buffer atomically.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

}  // namespace pleat
