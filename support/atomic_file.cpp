#include "support/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace pleat {

namespace {

std::runtime_error write_error(const std::filesystem::path& path, const std::string& what) {
  const std::string name = path == kStandardOutput ? std::string("standard output") : path.string();
  return std::runtime_error(name + ": cannot write: " + what);
}

struct Temporary {
  std::filesystem::path path;
  int slot = -1;
};

// Creates a unique temporary file next to `path` (mode 0666 less the umask, like any new output), listed for
// remove_uncommitted_files(), open for writing: returns its descriptor. The name is listed *before* the file
// is created, so that a signal at any moment finds every file this process created (a signal between listing
// and creating unlinks a name that does not exist yet).
int make_temporary_sibling(const std::filesystem::path& path, Temporary& made) {
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  for (int attempt = 0; attempt < 100; ++attempt) {
    Temporary candidate{temporary_path(dir, path.filename().string()), -1};
    candidate.slot = list_temporary(candidate.path);
    const int fd = ::open(candidate.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      made = std::move(candidate);
      return fd;
    }
    const int error = errno;
    unlist_temporary(candidate.slot);
    if (error != EEXIST)
      throw write_error(path,
                        "cannot create a temporary file beside it: " + std::string(std::strerror(error)));
  }
  throw write_error(path, "cannot create a temporary file: too many name collisions");
}

// A file descriptor behind a buffer of its own: ::write retried on EINTR and short writes, the errno of the
// first failure kept (for the message), seeks by lseek after draining. Owned descriptors are closed by
// close() or the destructor; nothing is written on destruction (an output abandoned before it is completed is
// not completed).
class DescriptorBuffer : public std::streambuf {
 public:
  DescriptorBuffer(int fd, bool owned) : m_fd(fd), m_owned(owned) { setp(m_data, m_data + sizeof m_data); }
  ~DescriptorBuffer() override {
    if (m_owned && m_fd >= 0) ::close(m_fd);
  }
  int error() const { return m_error; }
  bool failed() const { return m_failed; }
  /// Drains and closes (an owned descriptor); false on failure (error() says why).
  bool close() {
    const bool drained = drain();
    if (m_owned && m_fd >= 0) {
      if (::close(m_fd) != 0 && drained) fail(errno);
      m_fd = -1;
    }
    return !m_failed;
  }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (n <= 0) return 0;  // nothing to copy (s may then be null: an empty vector's data())
    if (n <= epptr() - pptr()) {
      std::memcpy(pptr(), s, std::size_t(n));
      pbump(int(n));
      return n;
    }
    if (!drain() || !write_all(s, std::size_t(n))) return 0;
    return n;
  }
  int sync() override { return drain() ? 0 : -1; }
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
    if (!drain()) return pos_type(off_type(-1));
    const int whence = dir == std::ios_base::beg ? SEEK_SET : dir == std::ios_base::cur ? SEEK_CUR : SEEK_END;
    const off_t at = ::lseek(m_fd, off_t(off), whence);
    return at < 0 ? pos_type(off_type(-1)) : pos_type(off_type(at));
  }
  pos_type seekpos(pos_type pos, std::ios_base::openmode which) override {
    return seekoff(off_type(pos), std::ios_base::beg, which);
  }

 private:
  void fail(int error) {
    if (!m_failed) m_error = error;
    m_failed = true;
  }
  bool write_all(const char* p, std::size_t n) {
    if (m_failed) return false;
    while (n > 0) {
      const ssize_t written = ::write(m_fd, p, n);
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) {
        fail(written < 0 ? errno : EIO);
        return false;
      }
      p += written;
      n -= std::size_t(written);
    }
    return true;
  }
  bool drain() {
    const bool written = write_all(pbase(), std::size_t(pptr() - pbase()));
    setp(m_data, m_data + sizeof m_data);
    return written;
  }
  int m_fd;
  bool m_owned;
  bool m_failed = false;
  int m_error = 0;
  char m_data[1 << 16];
};

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

}  // namespace

std::string write_failure_reason(int error) {
  switch (error) {
    case 0:
    case EIO:
      return "I/O error";
    case ENOSPC:
      return "no space left on device";
    case EDQUOT:
      return "disk quota exceeded";
    case EFBIG:
      return "file too large (over the file size limit, ulimit -f)";
    case EPIPE:
      return "broken pipe (the reader went away)";
    default:
      return std::strerror(error);
  }
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
    m_buffer = std::make_unique<DescriptorBuffer>(STDOUT_FILENO, /*owned=*/false);
    m_out.rdbuf(m_buffer.get());
    return;
  }
  Temporary temporary;
  const int fd = make_temporary_sibling(m_target, temporary);
  m_temporary = std::move(temporary.path);
  m_slot = temporary.slot;
  m_buffer = std::make_unique<DescriptorBuffer>(fd, /*owned=*/true);
  m_out.rdbuf(m_buffer.get());  // also clears the stream's state
}

AtomicFile::~AtomicFile() {
  if (m_committed || m_temporary.empty()) return;
  m_out.rdbuf(nullptr);
  m_buffer.reset();  // closes the temporary file
  std::error_code ignored;
  std::filesystem::remove(m_temporary, ignored);
  unlist_temporary(m_slot);  // after the removal: a signal in between finds the slot still listed
}

void AtomicFile::check() const {
  const auto& buffer = static_cast<const DescriptorBuffer&>(*m_buffer);
  if (buffer.failed() || !m_out) throw write_error(m_path, write_failure_reason(buffer.error()));
}

void AtomicFile::close() {
  if (m_closed) return;
  m_out.flush();
  auto& buffer = static_cast<DescriptorBuffer&>(*m_buffer);
  if (!buffer.close() || !m_out) throw write_error(m_path, write_failure_reason(buffer.error()));
  m_closed = true;
}

void AtomicFile::commit() {
  if (m_committed) throw std::logic_error("AtomicFile::commit called twice");
  close();
  if (m_temporary.empty()) {  // standard output
    m_committed = true;
    return;
  }
  // The target may have changed while the output was computed: still nothing but a regular file is replaced.
  std::error_code ec;
  refuse_unless_regular(m_path, std::filesystem::symlink_status(m_target, ec));
  std::filesystem::rename(m_temporary, m_target, ec);
  if (ec) throw write_error(m_path, "cannot rename the temporary file into place: " + ec.message());
  unlist_temporary(m_slot);
  m_slot = -1;
  m_committed = true;
}

StagedFiles::StagedFiles(std::filesystem::path directory) : m_directory(std::move(directory)) {
  std::filesystem::create_directories(m_directory);
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::filesystem::path candidate = temporary_path(m_directory, "pleat-staged");
    m_slot = list_temporary(candidate, /*directory=*/true);
    if (::mkdir(candidate.c_str(), 0777) == 0) {
      m_staging = std::move(candidate);
      return;
    }
    const int error = errno;
    unlist_temporary(m_slot);
    m_slot = -1;
    if (error != EEXIST)
      throw write_error(m_directory,
                        "cannot create a staging directory in it: " + std::string(std::strerror(error)));
  }
  throw write_error(m_directory, "cannot create a staging directory: too many name collisions");
}

StagedFiles::~StagedFiles() {
  if (m_committed) return;
  std::error_code ignored;
  std::filesystem::remove_all(m_staging, ignored);
  unlist_temporary(m_slot);
}

void StagedFiles::add(const std::string& name, std::string_view bytes) {
  const std::filesystem::path target = m_directory / name;
  resolve_output_target(target);  // refuses a directory, FIFO, device there
  const int fd = ::open((m_staging / name).c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw write_error(target, std::strerror(errno));
  DescriptorBuffer buffer(fd, /*owned=*/true);
  buffer.sputn(bytes.data(), std::streamsize(bytes.size()));
  if (!buffer.close()) throw write_error(target, write_failure_reason(buffer.error()));
  m_names.push_back(name);
}

void StagedFiles::commit() {
  namespace fs = std::filesystem;
  if (m_committed) throw std::logic_error("StagedFiles::commit called twice");
  for (const std::string& name : m_names) {
    const fs::path target = resolve_output_target(m_directory / name);
    std::error_code ec;
    fs::rename(m_staging / name, target, ec);
    if (ec.value() == EXDEV)  // a link to another file system: copied there atomically
      write_file_atomically(m_directory / name, [&](std::ostream& out) {
        std::ifstream in(m_staging / name, std::ios::binary);
        out << in.rdbuf();
      });
    else if (ec)
      throw write_error(m_directory / name, "cannot move it into place: " + ec.message());
  }
  std::error_code ignored;
  fs::remove_all(m_staging, ignored);
  unlist_temporary(m_slot);
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
