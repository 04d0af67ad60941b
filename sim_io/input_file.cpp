#include "sim_io/text_file.hpp"

#include "sim_io/input_error.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

namespace pleat {

std::string read_whole_file(const std::filesystem::path& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) throw InputError(path.string(), "", "no such file");
  if (std::filesystem::is_directory(status)) throw InputError(path.string(), "", "is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", std::string("cannot open: ") + std::strerror(errno));
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path.string(), "", "read error");
  return bytes;
}

}  // namespace pleat
