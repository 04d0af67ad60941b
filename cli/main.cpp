// pleat: per-vertex visibility cones on animated cloth, and shading from them.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "cli/commands.hpp"
#include "cli/global_options.hpp"
#include "cli/job_error.hpp"
#include "cli/memory_limit.hpp"
#include "cli/termination.hpp"
#include "cli/world.hpp"
#include "support/nearest_name.hpp"

namespace {

using pleat::cli::World;

// Under mpirun: an error every rank learnt of (JobError) is printed once by rank 0 and every rank exits with
// its code; an error of one rank alone ends the whole job (rank 0's temporary outputs are removed).
int fail(const std::string& message, int code, bool agreed) {
  if (!agreed && World::distributed()) {
    std::cerr << "pleat: error: rank " << World::rank() << ": " << message << '\n';
    World::abort(code);
  }
  if (World::root()) std::cerr << "pleat: error: " << message << '\n';
  World::finalize();
  return code;
}

// One line per unknown option left over by the main app or the subcommand given that is near an option name
// of that app (the global options included), "  --spcing: did you mean --spacing?", and when no subcommand
// was given, one for an unknown subcommand near a subcommand's name.
std::string suggestions(const CLI::App& app, const CLI::App& command) {
  std::string lines;
  for (const CLI::App* parsed : {&app, &command}) {
    if (parsed == &command && &command == &app) break;
    std::vector<std::string> options;
    for (const CLI::Option* option : parsed->get_options())
      for (const std::string& name : option->get_lnames()) options.push_back(name);
    for (const std::string& arg : parsed->remaining()) {
      const std::size_t start = arg.find_first_not_of('-');
      if (start == 0 || start == std::string::npos || arg.size() - start < 2) continue;  // a value, or -x
      const std::size_t equals = arg.find('=');
      const std::string typed = arg.substr(start, equals == std::string::npos ? equals : equals - start);
      const std::string name = pleat::nearest_name(typed, options);
      if (!name.empty()) lines += "  " + arg.substr(0, equals) + ": did you mean --" + name + "?\n";
    }
  }
  if (&command == &app) {
    std::vector<std::string> subcommands;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
      subcommands.push_back(sub->get_name());
    for (const std::string& arg : app.remaining())
      if (!arg.empty() && arg[0] != '-') {
        const std::string name = pleat::nearest_name(arg, subcommands);
        if (!name.empty()) lines += "  " + arg + ": did you mean `pleat " + name + "`?\n";
        break;
      }
  }
  return lines;
}

// A parse error: --help and --version print and exit 0; anything else is a usage error (exit status 2): what
// is wrong, a suggestion for each misspelt option, and a pointer to --help.
int parse_failure(const CLI::App& app, const CLI::ParseError& e) {
  // Every rank parses the same arguments: one of them says what is wrong.
  int code = pleat::cli::kUsage;
  if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) {
    code = pleat::cli::kSuccess;
    if (World::root()) app.exit(e);
  } else if (World::root()) {
    const auto used = app.get_subcommands();
    const CLI::App& command = used.empty() ? app : *used.front();
    std::string what = e.what();
    if (dynamic_cast<const CLI::ExtrasError*>(&e)) {  // CLI11 lists them last first
      what = "unexpected argument(s):";
      for (const std::string& arg : app.remaining(/*recurse=*/true)) what += " " + arg;
    }
    const std::string name = used.empty() ? "pleat" : "pleat " + command.get_name();
    std::cerr << "pleat: error: " << what << '\n'
              << suggestions(app, command) << "Run `" << name << " --help` for the options.\n";
  }
  World::finalize();
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  World::init(argc, argv);  // MPI only when launched by mpirun
  pleat::cli::install_termination_handler();
  CLI::App app{
      "pleat — visibility cones on animated cloth (Stewart 1999, kept alive frame to frame), and shading "
      "from them.\n"};
  app.require_subcommand(1);
  app.footer(
      "Examples:\n"
      "  pleat generate curtain -o curtain.obj --frames 60\n"
      "  pleat info data/drape/drape.obj --cache data/drape/drape.pc2 --check-intersections\n"
      "  pleat visibility curtain.obj --cache curtain.pc2 -o curtain.csv\n"
      "  pleat shade curtain.obj --cache curtain.pc2 -o curtain.glb --render renders/\n"
      "  pleat compare curtain.obj --cache curtain.pc2 --frame 20 --light sky:1 -o compare.png\n"
      "  pleat view curtain.glb -o curtain_view          # a page that relights it live\n"
      "Run `pleat SUBCOMMAND --help` for each subcommand's options.\n" +
      std::string(
          World::built_with_mpi()
              ? "MPI: built in; `mpirun -np N pleat visibility|shade ...` splits the frames over N ranks."
              : "MPI: not built in (PLEAT_MPI=OFF); pleat runs as one process."));
  pleat::cli::register_info_command(app);
  pleat::cli::register_generate_command(app);
  pleat::cli::register_visibility_command(app);
  pleat::cli::register_shade_command(app);
  pleat::cli::register_compare_command(app);
  pleat::cli::register_view_command(app);
  pleat::cli::add_global_options(app, PLEAT_VERSION);
  try {
    app.parse(argc, argv);  // runs the subcommand
  } catch (const CLI::ParseError& e) {
    return parse_failure(app, e);
  } catch (const pleat::cli::JobError& e) {
    return fail(e.what(), e.code(), true);
  } catch (const std::bad_alloc&) {
    return fail(pleat::cli::out_of_memory_message(), pleat::cli::kFailure, false);
  } catch (const std::exception& e) {
    return fail(e.what(), pleat::cli::exit_status_of(e), false);
  }
  pleat::cli::World::finalize();
  return pleat::cli::kSuccess;
}
