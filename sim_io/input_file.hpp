// Reading a whole input file into memory, with the InputError every reader gives for a missing,
// unreadable or non-regular file.
#pragma once

#include <filesystem>
#include <string>

namespace pleat {

/// The bytes of `path`. Throws InputError(path, "", ...) when it is missing, a directory, or unreadable.
std::string read_whole_file(const std::filesystem::path& path);

}  // namespace pleat
