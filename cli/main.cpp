// pleat: per-vertex visibility cones on animated cloth, and shading from them.
#include <cstdio>
#include <exception>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/distributed.hpp"
#include "cli/termination.hpp"
#include "static_core/input_error.hpp"

namespace {

// Under mpirun: an error every rank learnt of (JobError) is printed once by rank 0 and every rank exits with
// its code; an error of one rank alone ends the whole job (rank 0's temporary outputs are removed).
int fail(const std::string& message, int code, bool agreed) {
  using pleat::cli::World;
  if (!agreed && World::distributed()) {
    std::cerr << "pleat: error: rank " << World::rank() << ": " << message << '\n';
    World::abort(code);
  }
  if (World::root()) std::cerr << "pleat: error: " << message << '\n';
  World::finalize();
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  pleat::cli::World::init(argc, argv);  // MPI only when launched by mpirun
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
      "Run `pleat SUBCOMMAND --help` for each subcommand's options.");
  pleat::cli::register_info_command(app);
  pleat::cli::register_generate_command(app);
  pleat::cli::register_visibility_command(app);
  pleat::cli::register_shade_command(app);
  pleat::cli::register_compare_command(app);
  pleat::cli::register_view_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Every rank parses the same arguments: one of them says what is wrong.
    const int code = pleat::cli::World::root() ? app.exit(e) : e.get_exit_code();
    pleat::cli::World::finalize();
    return code;
  } catch (const pleat::cli::JobError& e) {
    return fail(e.what(), e.code(), true);
  } catch (const pleat::InputError& e) {
    return fail(e.what(), 2, false);
  } catch (const std::exception& e) {
    return fail(e.what(), 1, false);
  }
  pleat::cli::World::finalize();
  return 0;
}
