#include "cli/job_error.hpp"

#include <chrono>
#include <cstdint>
#include <optional>
#include <thread>

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

void on_rank_zero_alone(const std::function<void()>& step) {
  if (!World::distributed()) return step();
  constexpr int kDoneTag = 3;  // rank 0's exit status and error, to every other rank
  std::string word;
  if (World::root()) {
    std::int32_t code = 0;
    std::string what;
    try {
      step();
    } catch (const JobError& e) {
      code = e.code(), what = e.what();
    } catch (const std::exception& e) {
      code = exit_status_of(e), what = e.what();
    }
    word = ByteWriter().put<std::int32_t>(code).put_string(what).take();
    for (int r = 1; r < World::size(); ++r) World::send(r, kDoneTag, word);
    World::wait_sends();
  } else {
    std::optional<World::Message> message;
    while (!(message = World::receive(0, kDoneTag, /*wait=*/false)))
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    word = std::move(message->bytes);
  }
  ByteReader reader(word);
  const auto code = reader.get<std::int32_t>();
  if (code != 0) throw JobError(std::string(reader.get_string()), code);
}

}  // namespace pleat::cli
