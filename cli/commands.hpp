// The subcommands of `pleat`, one file each (cli/<name>_command.cpp).
#pragma once

#include <CLI/CLI.hpp>

namespace pleat::cli {

void register_info_command(CLI::App& app);
void register_generate_command(CLI::App& app);
void register_visibility_command(CLI::App& app);
void register_shade_command(CLI::App& app);
void register_compare_command(CLI::App& app);
void register_view_command(CLI::App& app);

}  // namespace pleat::cli
