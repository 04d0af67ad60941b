// A job's finished chunks kept in a directory (--checkpoint DIR), so that a rerun after a failure computes
// only the chunks missing. Each chunk is one file DIR/chunk_<first>_<last>.pleatchunk, written atomically
// (sim_io/atomic_file.hpp): a header (magic, job key, chunk key, frame range), one record per frame (frame
// number, byte count, the frame's bytes as the command encodes them) and an end marker. A chunk file is used
// again only when its job key and its chunk key both match (cli/chunk_plan.hpp says what they cover);
// files of another job are removed, with a line on stderr.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string_view>
#include <vector>

#include "sim_io/atomic_file.hpp"

namespace pleat::cli {

/// Where a frame's bytes go, in frame order.
using ConsumeFrame = std::function<void(std::size_t frame, std::string_view bytes)>;

class Checkpoint {
 public:
  Checkpoint(std::filesystem::path dir, std::uint64_t job_key);
  /// Names and checks DIR's chunk files against the job: returns, per chunk, whether it is kept and valid;
  /// removes chunk files of another job (another input, plan or options) and says so on stderr.
  std::vector<bool> scan(const std::vector<std::size_t>& bounds,
                         const std::vector<std::uint64_t>& chunk_keys);
  std::filesystem::path path_of(std::size_t first, std::size_t last) const;
  const std::filesystem::path& dir() const { return m_dir; }
  std::uint64_t job_key() const { return m_job_key; }
  /// Passes every frame of the kept chunk [first, last) to `consume`, in order; throws std::runtime_error
  /// naming the file, the frame and the byte if it is unreadable (truncated, a record of another frame, a
  /// record longer than what is left of the file), before allocating for such a record.
  void read(std::size_t first, std::size_t last, const ConsumeFrame& consume) const;

 private:
  std::filesystem::path m_dir;
  std::uint64_t m_job_key;
};

/// One chunk file being written: the frames added in order, in place once committed.
class ChunkFile {
 public:
  ChunkFile(const Checkpoint& checkpoint, std::size_t first, std::size_t last, std::uint64_t chunk_key);
  void add(std::size_t frame, std::string_view bytes);
  void commit();

 private:
  AtomicFile m_file;
};

}  // namespace pleat::cli
