#include "sim_io/atomic_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace pleat {

namespace {

std::runtime_error write_error(const std::filesystem::path& path, const std::string& what) {
  return std::runtime_error(path.string() + ": cannot write: " + what);
}

// Creates a unique temporary file next to `path` and returns its name (the file exists, empty).
std::filesystem::path make_temporary_sibling(const std::filesystem::path& path) {
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  std::string pattern = (dir / ("." + path.filename().string() + ".tmp.XXXXXX")).string();
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  const int fd = ::mkstemp(buffer.data());
  if (fd < 0) throw write_error(path, std::string("cannot create a temporary file: ") + std::strerror(errno));
  ::close(fd);
  return std::filesystem::path(buffer.data());
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  const std::filesystem::path temporary = make_temporary_sibling(path);
  try {
    {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      if (!out) throw write_error(path, "cannot open the temporary file " + temporary.string());
      write(out);
      out.flush();
      if (!out) throw write_error(path, "I/O error while writing");
      out.close();
      if (out.fail()) throw write_error(path, "I/O error while closing");
    }
    // mkstemp creates files with mode 0600; give the output the usual permissions (umask applies).
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::chmod(temporary.c_str(), 0666 & ~mask);
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) throw write_error(path, "cannot rename the temporary file into place: " + ec.message());
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
}

void write_file_atomically(const std::filesystem::path& path, const std::string& content) {
  write_file_atomically(path, [&](std::ostream& out) { out.write(content.data(), std::streamsize(content.size())); });
}

}  // namespace pleat
