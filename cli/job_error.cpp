#include "cli/job_error.hpp"

#include <cstdint>

#include "cli/global_options.hpp"
#include "cli/world.hpp"
#include "support/byte_stream.hpp"

namespace pleat::cli {

void agree(std::exception_ptr error) {
  if (!World::distributed()) {
    if (error) std::rethrow_exception(error);
    return;
  }
  int lowest = error ? World::rank() : World::size();
  World::all_reduce(std::span<int>(&lowest, 1), World::Reduction::Min);
  if (lowest == World::size()) return;
  std::string message;
  if (World::rank() == lowest) {
    std::string what = "unknown error";
    int code = 1;
    try {
      std::rethrow_exception(error);
    } catch (const JobError& e) {
      what = e.what(), code = e.code();
    } catch (const std::exception& e) {
      what = e.what(), code = exit_status_of(e);
    } catch (...) {
    }
    message = ByteWriter().put<std::int32_t>(code).put_string(what).take();
  }
  World::broadcast(message, lowest);
  ByteReader reader(message);
  const auto code = reader.get<std::int32_t>();
  throw JobError(std::string(reader.get_string()), code);
}

}  // namespace pleat::cli
