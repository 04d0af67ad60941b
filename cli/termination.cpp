#include "cli/termination.hpp"

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstring>

#include "cli/world.hpp"
#include "sim_io/atomic_file.hpp"

namespace pleat::cli {

namespace {

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
char g_messages[3][192];  // per signal, formatted at installation (the handler may not allocate)

extern "C" void on_termination(int signal) {
  remove_uncommitted_files();
  for (int i = 0; i < 3; ++i)
    if (kSignals[i] == signal && g_messages[i][0] != '\0') {
      [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, g_messages[i], std::strlen(g_messages[i]));
    }
  ::_exit(128 + signal);
}

}  // namespace

void install_termination_handler() {
  const char* const names[] = {"SIGINT", "SIGTERM", "SIGHUP"};
  struct sigaction action {};
  action.sa_handler = on_termination;
  sigemptyset(&action.sa_mask);
  for (int signal : kSignals) sigaddset(&action.sa_mask, signal);  // one handler at a time
  for (int i = 0; i < 3; ++i) {
    if (!World::root())
      g_messages[i][0] = '\0';
    else if (World::distributed())
      std::snprintf(g_messages[i], sizeof g_messages[i],
                    "pleat: error: the job was stopped (%s: a rank failed or was killed, or the job was "
                    "cancelled); unfinished outputs removed\n",
                    names[i]);
    else
      std::snprintf(g_messages[i], sizeof g_messages[i], "pleat: stopped by %s; unfinished outputs removed\n",
                    names[i]);
    struct sigaction previous {};
    sigaction(kSignals[i], nullptr, &previous);
    if (previous.sa_handler == SIG_IGN) continue;
    sigaction(kSignals[i], &action, nullptr);
  }
}

}  // namespace pleat::cli
