// Placeholder so the build links while the subcommand is being written; replaced in this session.
#include "cli/commands.hpp"
#include <stdexcept>
namespace pleat::cli {
void register_info_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "(being written)");
  cmd->callback([] { throw std::runtime_error("pleat info: not built yet"); });
}
}  // namespace pleat::cli
