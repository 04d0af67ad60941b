#include "cli/output_paths.hpp"

#include <fnmatch.h>
#include <sys/stat.h>

#include <stdexcept>

#include "cli/global_options.hpp"
#include "sim_io/input_formats.hpp"
#include "support/atomic_file.hpp"

namespace pleat::cli {

namespace {

namespace fs = std::filesystem;

// What a path is on disk: its device and inode when it exists (links followed), else the absolute path of
// the file it would be, its directory's links resolved.
struct FileIdentity {
  bool exists = false;
  dev_t device = 0;
  ino_t inode = 0;
  fs::path path;
};

FileIdentity identify(const fs::path& path) {
  FileIdentity id;
  struct stat info {};
  if (::stat(path.c_str(), &info) == 0) {
    id.exists = true;
    id.device = info.st_dev;
    id.inode = info.st_ino;
  }
  std::error_code ec;
  id.path = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) id.path = fs::absolute(path).lexically_normal();
  return id;
}

bool same_file(const FileIdentity& a, const FileIdentity& b) {
  if (a.exists && b.exists) return a.device == b.device && a.inode == b.inode;
  return !a.exists && !b.exists && a.path == b.path;
}

// Refuses `output` (option `option`) when it is one of `inputs`.
void refuse_an_input(const std::string& option, const std::string& output, const FileIdentity& id,
                     const std::vector<std::pair<InputFile, FileIdentity>>& inputs) {
  for (const auto& [input, input_id] : inputs) {
    if (!same_file(id, input_id)) continue;
    throw std::invalid_argument(option + " " + output + " is the input " + input.path + " (" + input.option +
                                (output == input.path ? "" : ", the same file under another name") +
                                "): pleat never writes over its inputs; give the output another path");
  }
}

// Refuses a directory output that exists and is not a directory, or that holds an input under a name it
// writes.
void check_directory(const OutputDirectory& directory,
                     const std::vector<std::pair<InputFile, FileIdentity>>& inputs) {
  if (directory.path == kStandardOutput)
    throw std::invalid_argument(directory.option + " -: this output is a directory");
  std::error_code ec;
  const fs::file_status status = fs::status(directory.path, ec);
  if (fs::exists(status) && !fs::is_directory(status))
    throw OutputRefused(directory.path,
                        "not a directory; " + directory.option + " writes files into a directory");
  const FileIdentity dir = identify(directory.path);
  for (const auto& [input, id] : inputs) {
    const FileIdentity parent = identify(id.path.parent_path());
    if (!same_file(parent, dir)) continue;
    const std::string name = id.path.filename().string();
    for (const std::string& pattern : directory.writes)
      if (::fnmatch(pattern.c_str(), name.c_str(), 0) == 0)
        throw std::invalid_argument(directory.option + " " + directory.path + " would write " + name +
                                    ", the file " + input.option + " " + input.path +
                                    " reads: pleat never writes over its inputs; give it another directory");
  }
}

}  // namespace

void create_parent_directory(const fs::path& output) {
  if (output == kStandardOutput) return;
  const fs::path target = resolve_output_target(output);
  if (target.has_parent_path()) fs::create_directories(target.parent_path());
}

std::vector<fs::path> files_read_for(const fs::path& path) { return files_read_by(path); }

void check_outputs(const std::vector<OutputFile>& files, const std::vector<OutputDirectory>& directories,
                   const std::vector<InputFile>& inputs) {
  std::vector<std::pair<InputFile, FileIdentity>> read;
  for (const InputFile& input : inputs)
    if (!input.path.empty() && input.path != kStandardOutput) read.emplace_back(input, identify(input.path));
  std::vector<std::pair<FileIdentity, std::string>> seen;  // outputs so far, and their options
  std::vector<fs::path> targets;
  for (const OutputFile& file : files) {
    if (file.path.empty()) continue;
    if (file.path == kStandardOutput) {
      if (!file.stdout_allowed)
        throw std::invalid_argument(file.option + " -: this output cannot be streamed to standard output");
      for (const auto& [other, option] : seen)
        if (other.path == kStandardOutput)
          throw std::invalid_argument(option + " and " + file.option +
                                      " both stream to standard output (-); give one of them a file");
      report_to_stderr();
      seen.emplace_back(FileIdentity{false, 0, 0, kStandardOutput}, file.option);
      continue;
    }
    const fs::path target = resolve_output_target(file.path);
    const FileIdentity id = identify(target);
    for (const auto& [other, option] : seen)
      if (same_file(other, id))
        throw std::invalid_argument(option + " and " + file.option + " name the same file (" + file.path +
                                    "); give each output its own");
    refuse_an_input(file.option, file.path, id, read);
    seen.emplace_back(id, file.option);
    targets.push_back(target);
  }
  for (const OutputDirectory& directory : directories)
    if (!directory.path.empty()) check_directory(directory, read);
  // Left over by dead processes where this run writes.
  for (const fs::path& target : targets)
    remove_stale_temporaries(target.has_parent_path() ? target.parent_path() : fs::path("."),
                             target.filename().string());
  for (const OutputDirectory& directory : directories)
    if (!directory.path.empty()) remove_stale_temporaries(directory.path);
}

}  // namespace pleat::cli
