// The paths a subcommand writes, checked before any work: each output is a file pleat may replace
// (support/atomic_file.hpp's resolve_output_target), no two outputs are one file, and no output is one of
// the inputs the run reads, through symbolic links and hard links (a file is its device and inode; one that
// does not exist yet, its directory and name with links resolved). Temporaries that dead processes of this
// machine left where the run will write are removed (support/temporary_files.hpp).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace pleat::cli {

/// Creates the directory an output file goes into (that of the file its symbolic links lead to), if missing;
/// nothing for "-" (standard output).
void create_parent_directory(const std::filesystem::path& output);

/// One output file of a subcommand: the option naming it, its path (empty: not asked for), and whether "-"
/// (standard output) may stand for it.
struct OutputFile {
  std::string option;
  std::string path;
  bool stdout_allowed = true;
};

/// A directory a subcommand writes files into (empty path: not asked for), and the names it writes there
/// (shell patterns: "frame_*.png").
struct OutputDirectory {
  std::string option;
  std::string path;
  std::vector<std::string> writes = {};
};

/// One file a subcommand reads: the option or argument naming it ("INPUT", "--cache", ...) and its path.
struct InputFile {
  std::string option;
  std::string path;
};

/// The files reading `path` as a cloth or occluder reads: a numbered OBJ sequence's or a directory's frame
/// files, a .gltf and the external buffers and images it names, or `path` itself. Never throws (a path that
/// does not read as what it seems is itself; its reader says what is wrong).
std::vector<std::filesystem::path> files_read_for(const std::filesystem::path& path);

/// Refuses, before any work, with a usage error (exit status 2): an output file whose path is not a regular
/// file after following links (resolve_output_target), "-" where it is not allowed or for two outputs, one
/// file named by two outputs, an output that is one of `inputs` (naming both), an output directory that
/// exists and is not a directory, and one holding an input under a name it writes. When an output is "-",
/// moves the lines saying what was written to stderr (report_to_stderr()). Then removes the temporaries
/// dead processes of this machine left for these outputs and in these directories.
void check_outputs(const std::vector<OutputFile>& files, const std::vector<OutputDirectory>& directories = {},
                   const std::vector<InputFile>& inputs = {});

}  // namespace pleat::cli
