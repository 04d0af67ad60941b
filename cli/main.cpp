// pleat: per-vertex visibility cones on animated cloth, and shading from them.
#include <cstdio>
#include <exception>
#include <iostream>

#include "cli/commands.hpp"
#include "static_core/input_error.hpp"

int main(int argc, char** argv) {
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
    return app.exit(e);
  } catch (const pleat::InputError& e) {
    std::cerr << "pleat: error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "pleat: error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
