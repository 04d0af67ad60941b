#include "cli/global_options.hpp"

#include <tbb/global_control.h>

#include <iostream>
#include <stdexcept>

#include "support/input_error.hpp"

namespace pleat::cli {

namespace {

GlobalOptions g_options;
bool g_report_to_stderr = false;
// --threads, for the rest of the process: never destroyed, as destroying it wakes TBB's workers, which
// throws from a destructor at exit when no thread can be created (a memory limit) and aborts the process.
tbb::global_control* g_threads = nullptr;

constexpr const char* kGroup = "Global options (before or after the subcommand)";

void add_to(CLI::App& command, const std::string& version) {
  command.set_version_flag("--version", "pleat " + version, "print pleat's version and exit")->group(kGroup);
  command
      .add_flag("-q,--quiet", g_options.quiet,
                "no lines saying what was written, no progress; warnings and errors still go to stderr")
      ->group(kGroup);
  command
      .add_option("--progress", g_options.progress,
                  "progress on stderr: bar (redrawn in place), lines (for logs: one line per 5% or 10 s, "
                  "'pleat: visibility 37/120 frames 30.8% 2.1 frames/s eta 40 s'), none, or auto (default: a "
                  "bar when stderr is a terminal, else none)")
      ->check(CLI::IsMember({"auto", "bar", "lines", "none"}))
      ->group(kGroup);
  command.add_option("--threads", g_options.threads, "threads for the whole run (default 0: all cores)")
      ->check(CLI::Range(0, 1 << 16))
      ->group(kGroup);
}

}  // namespace

const GlobalOptions& global_options() { return g_options; }

const std::string& help_footer() {
  static const std::string footer =
      "Exit status: 0 success; 1 runtime failure (I/O, out of memory, internal error); 2 usage error or bad\n"
      "input (an unknown option or bad value, an input pleat cannot read, an output path it refuses: one "
      "that\n"
      "is an input, through links too). Stopped by a signal (SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGXCPU, "
      "...):\n"
      "128 + the signal, the temporary files of unfinished outputs removed.\n"
      "Outputs: each is written to a hidden temporary file beside it (.NAME.tmp.HOST.PID.N) and all are "
      "renamed\n"
      "into place together when complete, so a failed or stopped run leaves the previous files, or none; a "
      "later\n"
      "run removes what a killed one left. A symbolic link is written through (it stays a link); a "
      "directory,\n"
      "FIFO or device is refused before any work. `-o -` streams to standard output (not atomically; the "
      "lines\n"
      "saying what was written then go to stderr).";
  return footer;
}

void add_global_options(CLI::App& app, const std::string& version) {
  for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) {
    add_to(*command, version);
    command->footer(command->get_footer() + "\n\n" + help_footer());
  }
  add_to(app, version);
  app.footer(app.get_footer() + "\n\n" + help_footer());
  // The main app's parse-complete callback runs after every option is parsed and checked, before the
  // subcommand's callback (which does the work).
  app.parse_complete_callback([] {
    if (g_options.threads > 0 && !g_threads)
      g_threads = new tbb::global_control(tbb::global_control::max_allowed_parallelism,
                                          std::size_t(g_options.threads));
  });
}

int exit_status_of(const std::exception& error) {
  if (dynamic_cast<const ArgumentError*>(&error))
    return kFailure;  // pleat handed an entry a bad frame: a bug
  if (dynamic_cast<const InputError*>(&error) || dynamic_cast<const std::invalid_argument*>(&error))
    return kUsage;
  return kFailure;
}

ProgressMode progress_mode(bool terminal) {
  const std::string& mode = g_options.progress;
  if (mode == "bar") return ProgressMode::Bar;
  if (mode == "lines") return ProgressMode::Lines;
  if (mode == "none" || (mode.empty() && g_options.quiet)) return ProgressMode::None;
  return terminal ? ProgressMode::Bar : ProgressMode::None;
}

std::ostream& report() {
  static std::ostream nowhere(nullptr);
  if (g_options.quiet) return nowhere;
  return g_report_to_stderr ? std::cerr : std::cout;
}

void report_to_stderr() { g_report_to_stderr = true; }

}  // namespace pleat::cli
