#include "support/temporary_files.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <string_view>
#include <system_error>

namespace pleat {

namespace {

// ---- The list: blocks of fixed slots of plain characters (a handler reads them without allocating);
// blocks are added when every slot is taken and never freed. A slot is free, being written (the handler
// skips it) or live.
enum SlotState : int { kFree, kWriting, kLive };
struct Slot {
  std::atomic<int> state{kFree};
  bool directory = false;
  char path[4096];
};
constexpr int kSlotsPerBlock = 32;
struct Block {
  Slot slots[kSlotsPerBlock];
  std::atomic<Block*> next{nullptr};
};
Block g_first;

Slot* slot_at(int id) noexcept {
  Block* block = &g_first;
  for (int b = 0; b < id / kSlotsPerBlock && block; ++b) block = block->next.load(std::memory_order_acquire);
  return block ? &block->slots[id % kSlotsPerBlock] : nullptr;
}

// Removes the files of `path` (a directory holding files only), then the directory. Async-signal-safe. Passes
// are repeated, as entries removed while the directory is read may make the reading skip others.
void remove_flat_directory(const char* path) noexcept {
  for (int pass = 0; pass < 4 && ::rmdir(path) != 0 && errno == ENOTEMPTY; ++pass) {
    const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    alignas(8) char buffer[4096];
    for (ssize_t n; (n = ::getdents64(fd, buffer, sizeof buffer)) > 0;)
      for (ssize_t at = 0; at < n;) {
        const auto* entry = reinterpret_cast<const struct dirent64*>(buffer + at);
        const char* name = entry->d_name;
        if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0) ::unlinkat(fd, name, 0);
        at += entry->d_reclen;
      }
    ::close(fd);
  }
}

// ---- Names

// This machine's name as it appears in temporary names: letters, digits, '-' and '_' (anything else, the
// dots of a qualified name included, becomes '_'), at most 64 characters.
const std::string& host_name() {
  static const std::string name = [] {
    char buffer[256] = {};
    if (::gethostname(buffer, sizeof buffer - 1) != 0 || buffer[0] == '\0') return std::string("localhost");
    std::string text(buffer, std::min<std::size_t>(std::strlen(buffer), 64));
    for (char& c : text)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) c = '_';
    return text;
  }();
  return name;
}

// The process id of a temporary of this machine named `.TARGET.tmp.HOST.PID.N` (TARGET == `target`, or any
// when `target` is empty), or 0 when `name` is not one.
pid_t owner_of(std::string_view name, std::string_view target) {
  const std::string tag = ".tmp." + host_name() + ".";
  const std::size_t at = name.rfind(tag);
  if (name.size() < 2 || name[0] != '.' || at == std::string_view::npos || at < 2) return 0;
  if (!target.empty() && name.substr(1, at - 1) != target) return 0;
  const std::string_view rest = name.substr(at + tag.size());  // "PID.N"
  const std::size_t dot = rest.find('.');
  if (dot == std::string_view::npos || dot == 0 || dot + 1 == rest.size()) return 0;
  long pid = 0;
  unsigned long counter = 0;
  const auto [pid_end, pid_error] = std::from_chars(rest.data(), rest.data() + dot, pid);
  const auto [n_end, n_error] = std::from_chars(rest.data() + dot + 1, rest.data() + rest.size(), counter);
  if (pid_error != std::errc() || pid_end != rest.data() + dot || n_error != std::errc() ||
      n_end != rest.data() + rest.size() || pid <= 0)
    return 0;
  return static_cast<pid_t>(pid);
}

// ---- The commit window: -1 none open, 0 open with no signal held, else the signal held.
std::atomic<int> g_held{-1};
std::atomic<void (*)(int)> g_held_handler{nullptr};

}  // namespace

std::filesystem::path temporary_path(const std::filesystem::path& directory, const std::string& name) {
  static std::atomic<unsigned> counter{0};
  return directory / ("." + name + ".tmp." + host_name() + "." + std::to_string(::getpid()) + "." +
                      std::to_string(counter++));
}

int list_temporary(const std::filesystem::path& path, bool directory) {
  const std::string& text = path.native();
  if (text.size() >= sizeof g_first.slots[0].path) return -1;
  Block* block = &g_first;
  for (int b = 0;; ++b) {
    for (int i = 0; i < kSlotsPerBlock; ++i) {
      Slot& slot = block->slots[i];
      int expected = kFree;
      if (!slot.state.compare_exchange_strong(expected, kWriting)) continue;
      std::memcpy(slot.path, text.c_str(), text.size() + 1);
      slot.directory = directory;
      slot.state.store(kLive);
      return b * kSlotsPerBlock + i;
    }
    Block* next = block->next.load(std::memory_order_acquire);
    if (!next) {
      auto* fresh = new Block;  // never freed: a handler may be reading it
      if (block->next.compare_exchange_strong(next, fresh, std::memory_order_acq_rel))
        next = fresh;
      else
        delete fresh;  // another thread linked one first: `next` is it
    }
    block = next;
  }
}

void unlist_temporary(int slot) noexcept {
  if (slot < 0) return;
  if (Slot* s = slot_at(slot)) s->state.store(kFree);
}

void remove_uncommitted_files() noexcept {
  for (Block* block = &g_first; block; block = block->next.load(std::memory_order_acquire))
    for (Slot& slot : block->slots) {
      if (slot.state.load() != kLive) continue;
      if (slot.directory)
        remove_flat_directory(slot.path);
      else
        ::unlink(slot.path);
    }
}

std::size_t remove_stale_temporaries(const std::filesystem::path& directory, const std::string& name) {
  namespace fs = std::filesystem;
  std::size_t removed = 0;
  std::error_code ec;
  fs::directory_iterator it(directory.empty() ? fs::path(".") : directory, ec);
  for (; !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const pid_t pid = owner_of(it->path().filename().native(), name);
    if (pid == 0 || pid == ::getpid()) continue;
    if (::kill(pid, 0) == 0 || errno != ESRCH) continue;  // alive (or not ours to signal): keep it
    std::error_code removal;
    if (fs::remove_all(it->path(), removal) > 0 && !removal) ++removed;
  }
  return removed;
}

CommitWindow::CommitWindow() { g_held.store(0); }

CommitWindow::~CommitWindow() {
  const int held = g_held.exchange(-1);
  if (held > 0)
    if (void (*handler)(int) = g_held_handler.load()) handler(held);
}

bool hold_back_termination(int signal) noexcept {
  int expected = 0;
  if (g_held.compare_exchange_strong(expected, signal)) return true;
  return expected > 0;  // one held already; -1: no window open
}

void on_held_termination(void (*handler)(int)) noexcept { g_held_handler.store(handler); }

}  // namespace pleat
