#include "sim_io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace pleat {

namespace {

std::runtime_error write_error(const std::filesystem::path& path, const std::string& what) {
  return std::runtime_error(path.string() + ": cannot write: " + what);
}

// Creates a unique temporary file next to `path` (mode 0666 less the umask, like any new output) and
// returns its name; the file exists, empty.
std::filesystem::path make_temporary_sibling(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string name = ".";
    name += path.filename().string();
    name += ".tmp.";
    name += std::to_string(::getpid());
    name += '.';
    name += std::to_string(counter++);
    std::filesystem::path candidate = dir / name;
    const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return candidate;
    }
    if (errno != EEXIST)
      throw write_error(path, "cannot create a temporary file: " + std::string(std::strerror(errno)));
  }
  throw write_error(path, "cannot create a temporary file: too many name collisions");
}

// The live temporary files, for remove_uncommitted_files() from a signal handler: fixed slots of plain
// characters (no allocation there); a temporary whose path does not fit is simply not listed.
struct TemporarySlot {
  std::atomic<bool> used{false};
  char path[4096];
};
TemporarySlot g_temporaries[64];

int register_temporary(const std::filesystem::path& path) {
  const std::string& text = path.native();
  if (text.size() >= sizeof g_temporaries[0].path) return -1;
  for (int i = 0; i < 64; ++i) {
    bool expected = false;
    if (g_temporaries[i].used.load() || !g_temporaries[i].used.compare_exchange_strong(expected, true))
      continue;
    std::memcpy(g_temporaries[i].path, text.c_str(), text.size() + 1);
    return i;
  }
  return -1;
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_temporaries[slot].used.store(false);
}

}  // namespace

void remove_uncommitted_files() noexcept {
  for (TemporarySlot& slot : g_temporaries)
    if (slot.used.load()) ::unlink(slot.path);
}

AtomicFile::AtomicFile(std::filesystem::path path) : m_path(std::move(path)) {
  if (m_path.empty() || m_path.filename().empty()) throw write_error(m_path, "no file name");
  m_temporary = make_temporary_sibling(m_path);
  m_out.open(m_temporary, std::ios::binary | std::ios::trunc);
  if (!m_out) {
    std::error_code ignored;
    std::filesystem::remove(m_temporary, ignored);
    throw write_error(m_path, "cannot open the temporary file " + m_temporary.string());
  }
  m_slot = register_temporary(m_temporary);
}

AtomicFile::~AtomicFile() {
  if (m_committed) return;
  unregister_temporary(m_slot);
  m_out.close();
  std::error_code ignored;
  std::filesystem::remove(m_temporary, ignored);
}

void AtomicFile::commit() {
  if (m_committed) throw std::logic_error("AtomicFile::commit called twice");
  m_out.flush();
  if (!m_out) throw write_error(m_path, "I/O error while writing");
  m_out.close();
  if (m_out.fail()) throw write_error(m_path, "I/O error while closing");
  std::error_code ec;
  unregister_temporary(m_slot);
  m_slot = -1;
  std::filesystem::rename(m_temporary, m_path, ec);
  if (ec) throw write_error(m_path, "cannot rename the temporary file into place: " + ec.message());
  m_committed = true;
}

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write) {
  AtomicFile file(path);
  write(file.stream());
  file.commit();
}

void write_file_atomically(const std::filesystem::path& path, const std::string& content) {
  write_file_atomically(
      path, [&](std::ostream& out) { out.write(content.data(), std::streamsize(content.size())); });
}

}  // namespace pleat
