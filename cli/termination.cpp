#include "cli/termination.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <vector>

#include "cli/world.hpp"
#include "support/temporary_files.hpp"

namespace pleat::cli {

namespace {

enum class Kind { Stop, Crash };
struct HandledSignal {
  int signal;
  const char* name;
  const char* why;  // appended to "stopped by NAME" (may be empty)
  Kind kind;
  bool always;  // installed over another handler (not over SIG_IGN)
};

constexpr HandledSignal kSignals[] = {
    {SIGINT, "SIGINT", "", Kind::Stop, true},
    {SIGTERM, "SIGTERM", "", Kind::Stop, true},
    {SIGHUP, "SIGHUP", "", Kind::Stop, true},
    {SIGQUIT, "SIGQUIT", "", Kind::Stop, false},
    {SIGPIPE, "SIGPIPE", " (the reader of a pipe it wrote to went away)", Kind::Stop, false},
    {SIGXCPU, "SIGXCPU", " (the CPU time limit was reached: ulimit -t)", Kind::Stop, false},
    {SIGXFSZ, "SIGXFSZ", "", Kind::Stop, false},
    {SIGUSR1, "SIGUSR1", "", Kind::Stop, false},
    {SIGUSR2, "SIGUSR2", "", Kind::Stop, false},
    {SIGALRM, "SIGALRM", "", Kind::Stop, false},
    {SIGVTALRM, "SIGVTALRM", "", Kind::Stop, false},
    {SIGPROF, "SIGPROF", "", Kind::Stop, false},
    {SIGPOLL, "SIGPOLL", "", Kind::Stop, false},
    {SIGPWR, "SIGPWR", "", Kind::Stop, false},
    {SIGSTKFLT, "SIGSTKFLT", "", Kind::Stop, false},
    {SIGSEGV, "SIGSEGV", "", Kind::Crash, false},
    {SIGBUS, "SIGBUS", "", Kind::Crash, false},
    {SIGILL, "SIGILL", "", Kind::Crash, false},
    {SIGFPE, "SIGFPE", "", Kind::Crash, false},
    {SIGABRT, "SIGABRT", "", Kind::Crash, false},
    {SIGSYS, "SIGSYS", "", Kind::Crash, false},
    {SIGTRAP, "SIGTRAP", "", Kind::Crash, false},
};
constexpr int kMaxSignal = 65;

// Per signal, formatted at installation (a handler may not allocate): the line on stderr, the kind, and for
// crashes the action to go on to.
char g_messages[kMaxSignal][224];
Kind g_kind[kMaxSignal];
struct sigaction g_previous[kMaxSignal];

void say(int signal) {
  if (g_messages[signal][0] != '\0') {
    [[maybe_unused]] const ssize_t n =
        ::write(STDERR_FILENO, g_messages[signal], std::strlen(g_messages[signal]));
  }
}

// Ends the process for a stop signal (also called when a commit window holding it closes).
[[noreturn]] void stop(int signal) {
  remove_uncommitted_files();
  say(signal);
  ::_exit(128 + signal);
}

extern "C" void on_signal(int signal, siginfo_t* info, void*) {
  if (signal <= 0 || signal >= kMaxSignal) return;
  const bool sent = info == nullptr || info->si_code <= 0;  // by kill(), raise(), sigqueue()
  if (signal == SIGXFSZ && info && info->si_code == SI_USER && info->si_pid == ::getpid())
    return;  // the kernel's, for a file past the size limit: the write fails with EFBIG and says so
  if (g_kind[signal] == Kind::Crash) {
    remove_uncommitted_files();
    say(signal);
    sigaction(signal, &g_previous[signal], nullptr);
    if (sent) raise(signal);  // delivered when this returns; a fault repeats by itself
    return;
  }
  if (hold_back_termination(signal)) return;  // outputs being renamed together: after them
  stop(signal);
}

void format_message(const HandledSignal& s) {
  char* message = g_messages[s.signal];
  const std::size_t size = sizeof g_messages[s.signal];
  if (!World::root())
    message[0] = '\0';
  else if (s.kind == Kind::Crash)
    std::snprintf(message, size, "pleat: error: internal failure (%s); unfinished outputs removed\n", s.name);
  else if (World::distributed())
    std::snprintf(message, size,
                  "pleat: error: the job was stopped (%s%s: a rank failed or was killed, or the job was "
                  "cancelled); unfinished outputs removed\n",
                  s.name, s.why);
  else
    std::snprintf(message, size, "pleat: stopped by %s%s; unfinished outputs removed\n", s.name, s.why);
}

}  // namespace

void install_termination_handler() {
  // A CPU time limit whose soft and hard values are one (bash's `ulimit -t`) ends the process with SIGKILL,
  // which cannot be handled: one second below it, SIGXCPU comes first.
  struct rlimit cpu {};
  if (getrlimit(RLIMIT_CPU, &cpu) == 0 && cpu.rlim_cur != RLIM_INFINITY && cpu.rlim_cur == cpu.rlim_max &&
      cpu.rlim_cur > 1) {
    cpu.rlim_cur -= 1;
    setrlimit(RLIMIT_CPU, &cpu);
  }
  struct sigaction action {};
  action.sa_sigaction = on_signal;
  action.sa_flags = SA_SIGINFO;
  sigemptyset(&action.sa_mask);
  for (const HandledSignal& s : kSignals)  // one stop at a time
    if (s.kind == Kind::Stop) sigaddset(&action.sa_mask, s.signal);
  on_held_termination(stop);
  // The real-time signals terminate by default too: SIGRTMIN+n, where nothing handles them already.
  static char names[kMaxSignal][16];
  std::vector<HandledSignal> signals(std::begin(kSignals), std::end(kSignals));
  for (int signal = SIGRTMIN; signal <= SIGRTMAX && signal < kMaxSignal; ++signal) {
    std::snprintf(names[signal], sizeof names[signal], "SIGRTMIN+%d", signal - SIGRTMIN);
    signals.push_back({signal, names[signal], "", Kind::Stop, false});
  }
  for (const HandledSignal& s : signals) {
    format_message(s);
    g_kind[s.signal] = s.kind;
    struct sigaction previous {};
    sigaction(s.signal, nullptr, &previous);
    const bool handled = (previous.sa_flags & SA_SIGINFO) != 0 || previous.sa_handler != SIG_DFL;
    if (!(previous.sa_flags & SA_SIGINFO) && previous.sa_handler == SIG_IGN) continue;  // stays ignored
    if (handled && !s.always && s.kind == Kind::Stop) continue;  // some library's: kept
    g_previous[s.signal] = previous;
    sigaction(s.signal, &action, nullptr);
  }
}

}  // namespace pleat::cli
