// Placeholder so the build links while the subcommand is being written; replaced in this session.
#include "cli/commands.hpp"
#include <stdexcept>
namespace pleat::cli {
void register_visibility_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("visibility", "(being written)");
  cmd->callback([] { throw std::runtime_error("pleat visibility: not built yet"); });
}
}  // namespace pleat::cli
