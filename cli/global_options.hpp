// What holds for a whole `pleat` run, whatever the subcommand: the global options (--version, -q/--quiet,
// --progress, --threads), accepted before or after the subcommand's name; where messages go; the exit status;
// and the shared end of every `--help` (exit status, how outputs are written).
#pragma once

#include <CLI/CLI.hpp>
#include <exception>
#include <ostream>
#include <string>

namespace pleat::cli {

struct GlobalOptions {
  bool quiet = false;    ///< no "wrote ..." lines and no progress; warnings and errors still on stderr
  std::string progress;  ///< auto | bar | lines | none; empty: not given (auto, or none with --quiet)
  int threads = 0;       ///< threads for the whole run; 0: all cores
};

/// The options of this run, as parsed.
const GlobalOptions& global_options();

/// Adds the global options to `app` and to each of its subcommands (call after registering them), appends
/// the shared help footer to each, and applies --threads (tbb::global_control, kept for the rest of the
/// process) once parsing is complete, before the subcommand runs.
void add_global_options(CLI::App& app, const std::string& version);

/// Exit status: 0 success, 1 runtime failure (I/O, internal), 2 usage error or bad input.
enum ExitStatus { kSuccess = 0, kFailure = 1, kUsage = 2 };

/// The exit status of a run that failed with `error`: kUsage for bad input or usage (InputError, which
/// includes refused outputs; std::invalid_argument, which the CLI's argument checks and the parsers of
/// --light, --camera, --frames throw), kFailure for anything else, ArgumentError included (a library entry
/// handed a bad frame by pleat itself: a bug).
int exit_status_of(const std::exception& error);

/// "Exit status: ..." and "Outputs: ...", the end of every subcommand's --help.
const std::string& help_footer();

enum class ProgressMode { Bar, Lines, None };
/// How progress is shown: as --progress says; `auto` (the default): a bar when `terminal` (stderr is one, or
/// under mpirun the launcher's), none otherwise; none with --quiet unless --progress is given.
ProgressMode progress_mode(bool terminal);

/// Where the lines saying what was written go: standard output; standard error once an output streams to
/// standard output (report_to_stderr()); nowhere with --quiet. Warnings and errors go to std::cerr.
std::ostream& report();
/// An output of this run streams to standard output ("-"): report() moves to standard error.
void report_to_stderr();

}  // namespace pleat::cli
