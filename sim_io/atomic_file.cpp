#include "sim_io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace pleat {

namespace {

std::runtime_error write_error(const std::filesystem::path& path, const std::string& what) {
  return std::runtime_error(path.string() + ": cannot write: " + what);
}

// The live temporary files, for remove_uncommitted_files() from a signal handler: fixed slots of plain
// characters (no allocation there); a temporary whose path does not fit is simply not listed. A slot is
// free, being written (the handler skips it) or live.
enum SlotState : int { kFree, kWriting, kLive };
struct TemporarySlot {
  std::atomic<int> state{kFree};
  char path[4096];
};
TemporarySlot g_temporaries[64];

int register_temporary(const std::filesystem::path& path) {
  const std::string& text = path.native();
  if (text.size() >= sizeof g_temporaries[0].path) return -1;
  for (int i = 0; i < 64; ++i) {
    int expected = kFree;
    if (!g_temporaries[i].state.compare_exchange_strong(expected, kWriting)) continue;
    std::memcpy(g_temporaries[i].path, text.c_str(), text.size() + 1);
    g_temporaries[i].state.store(kLive);
    return i;
  }
  return -1;
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_temporaries[slot].state.store(kFree);
}

struct Temporary {
  std::filesystem::path path;
  int slot = -1;
};

// Creates a unique temporary file next to `path` (mode 0666 less the umask, like any new output), listed for
// remove_uncommitted_files(); the file exists, empty. The name is listed *before* the file is created, so
// that a signal at any moment finds every file this process created (a signal between listing and creating
// unlinks a name that does not exist yet, or, on a collision, a stale temporary of an earlier process of the
// same pid: the name holds the pid).
Temporary make_temporary_sibling(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string name = ".";
    name += path.filename().string();
    name += ".tmp.";
    name += std::to_string(::getpid());
    name += '.';
    name += std::to_string(counter++);
    Temporary candidate{dir / name, -1};
    candidate.slot = register_temporary(candidate.path);
    const int fd = ::open(candidate.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return candidate;
    }
    const int error = errno;
    unregister_temporary(candidate.slot);
    if (error != EEXIST)
      throw write_error(path, "cannot create a temporary file: " + std::string(std::strerror(error)));
  }
  throw write_error(path, "cannot create a temporary file: too many name collisions");
}

// Refuses `path` (as given) when what it leads to exists and is not a regular file.
void refuse_unless_regular(const std::filesystem::path& path, const std::filesystem::file_status& status) {
  namespace fs = std::filesystem;
  if (!fs::exists(status) || fs::is_regular_file(status)) return;
  std::string kind = "not a regular file";
  switch (status.type()) {
    case fs::file_type::directory:
      kind = "a directory";
      break;
    case fs::file_type::fifo:
      kind = "a FIFO";
      break;
    case fs::file_type::socket:
      kind = "a socket";
      break;
    case fs::file_type::character:
      kind = "a character device";
      break;
    case fs::file_type::block:
      kind = "a block device";
      break;
    case fs::file_type::symlink:
      kind = "a symbolic link made while pleat was writing";
      break;
    default:
      break;
  }
  std::string what =
      "not a regular file (" + kind + "); pleat writes outputs atomically and does not replace it";
  if (status.type() == fs::file_type::fifo || status.type() == fs::file_type::character)
    what += " (to write to standard output, give -)";
  throw OutputRefused(path, what);
}

// Standard output (file descriptor 1) behind a buffer of its own; ::write is retried on EINTR and short
// writes. Nothing is written on destruction: an output abandoned before commit() is not completed.
class StandardOutputBuffer : public std::streambuf {
 public:
  StandardOutputBuffer() { setp(m_data, m_data + sizeof m_data); }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    for (const char* p = pbase(); p < pptr();) {
      const ssize_t n = ::write(STDOUT_FILENO, p, std::size_t(pptr() - p));
      if (n < 0 && errno != EINTR) return false;
      if (n > 0) p += n;
    }
    setp(m_data, m_data + sizeof m_data);
    return true;
  }
  char m_data[1 << 16];
};

}  // namespace

void remove_uncommitted_files() noexcept {
  for (TemporarySlot& slot : g_temporaries)
    if (slot.state.load() == kLive) ::unlink(slot.path);
}

std::filesystem::path resolve_output_target(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  if (path == kStandardOutput) return path;
  // What the kernel finds at the path, links followed (it also follows /proc's links to pipes and terminals,
  // which have no path of their own).
  std::error_code ec;
  const fs::file_status found = fs::status(path, ec);
  if (ec.value() == ELOOP) throw OutputRefused(path, "too many levels of symbolic links");
  refuse_unless_regular(path, found);
  // The file the link chain names, read link by link (a dangling link names the file to create).
  fs::path target = path;
  for (int links = 0; fs::is_symlink(fs::symlink_status(target, ec)); ++links) {
    if (links == 40) throw OutputRefused(path, "too many levels of symbolic links");
    const fs::path next = fs::read_symlink(target, ec);
    if (ec)
      throw OutputRefused(path, "cannot read the symbolic link " + target.string() + ": " + ec.message());
    target = next.is_absolute() ? next : target.parent_path() / next;
  }
  const fs::file_status named = fs::symlink_status(target, ec);
  refuse_unless_regular(path, named);
  if (fs::exists(found) && !fs::exists(named))
    throw OutputRefused(path,
                        "its symbolic links lead to no file pleat can replace (" + target.string() + ")");
  return target;
}

AtomicFile::AtomicFile(std::filesystem::path path) : m_path(std::move(path)), m_out(nullptr) {
  if (m_path.empty() || m_path.filename().empty()) throw write_error(m_path, "no file name");
  m_target = resolve_output_target(m_path);
  if (m_target == kStandardOutput) {
    std::fflush(stdout);  // anything already on standard output goes first
    m_buffer = std::make_unique<StandardOutputBuffer>();
    m_out.rdbuf(m_buffer.get());
    return;
  }
  Temporary temporary = make_temporary_sibling(m_target);
  m_temporary = std::move(temporary.path);
  m_slot = temporary.slot;
  auto file = std::make_unique<std::filebuf>();
  if (!file->open(m_temporary, std::ios::out | std::ios::binary | std::ios::trunc)) {
    std::error_code ignored;
    std::filesystem::remove(m_temporary, ignored);
    unregister_temporary(m_slot);
    throw write_error(m_path, "cannot open the temporary file " + m_temporary.string());
  }
  m_buffer = std::move(file);
  m_out.rdbuf(m_buffer.get());  // also clears the stream's state
}

AtomicFile::~AtomicFile() {
  if (m_committed || m_temporary.empty()) return;
  m_out.rdbuf(nullptr);
  m_buffer.reset();  // closes the temporary file
  std::error_code ignored;
  std::filesystem::remove(m_temporary, ignored);
  unregister_temporary(m_slot);  // after the removal: a signal in between finds the slot still listed
}

void AtomicFile::commit() {
  if (m_committed) throw std::logic_error("AtomicFile::commit called twice");
  m_out.flush();
  if (!m_out) throw write_error(m_path, "I/O error while writing");
  if (m_temporary.empty()) {  // standard output
    m_committed = true;
    return;
  }
  if (!static_cast<std::filebuf&>(*m_buffer).close()) throw write_error(m_path, "I/O error while closing");
  // The target may have changed while the output was computed: still nothing but a regular file is replaced.
  std::error_code ec;
  refuse_unless_regular(m_path, std::filesystem::symlink_status(m_target, ec));
  std::filesystem::rename(m_temporary, m_target, ec);
  if (ec) throw write_error(m_path, "cannot rename the temporary file into place: " + ec.message());
  unregister_temporary(m_slot);
  m_slot = -1;
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
