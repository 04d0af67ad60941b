// A job's finished chunks kept in a directory (--checkpoint DIR), so that a rerun after a failure computes
// only the chunks missing. Each chunk is one file DIR/chunk_<first>_<last>.pleatchunk, written atomically
// (support/atomic_file.hpp): a header (magic "PLEATCK2", the chunk's key, its frame range, the header's
// CRC-32), one record per frame (frame number, byte count, the CRC-32 of the frame's bytes, the bytes as the
// command encodes them) and an end marker. The key covers what decides the chunk's bytes
// (cli/chunk_plan.hpp): a chunk is used again when its name and key are the job's and every checksum matches.
//
// Several tasks may share one directory (a farm's tasks over different --frames): a chunk of a range the job
// does not have is left alone. One of the job's ranges made for another input, plan or command is replaced,
// and a damaged one (a checksum that does not match, a truncated file) is named as damaged on stderr and
// computed again. Temporaries that dead processes of this machine left there are removed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string_view>
#include <vector>

#include "support/atomic_file.hpp"

namespace pleat::cli {

/// Where a frame's bytes go, in frame order.
using ConsumeFrame = std::function<void(std::size_t frame, std::string_view bytes)>;

class Checkpoint {
 public:
  explicit Checkpoint(std::filesystem::path dir);
  /// Checks the chunk files of the job's chunks (`bounds`, and their `chunk_keys`) in DIR: returns, per
  /// chunk, whether it is kept, read whole and every checksum matching; removes those of the job's chunks
  /// made for another input, plan or command, and those damaged, and says so on stderr. Cost: reads every
  /// kept chunk once.
  std::vector<bool> scan(const std::vector<std::size_t>& bounds,
                         const std::vector<std::uint64_t>& chunk_keys);
  std::filesystem::path path_of(std::size_t first, std::size_t last) const;
  const std::filesystem::path& dir() const { return m_dir; }
  /// Passes every frame of the kept chunk [first, last) of key `chunk_key` to `consume`, in order; throws
  /// std::runtime_error naming the file, the frame and the byte if it is damaged (truncated, a record of
  /// another frame, a record longer than what is left of the file, a checksum that does not match), before
  /// allocating for such a record, or if it is another key's.
  void read(std::size_t first, std::size_t last, std::uint64_t chunk_key, const ConsumeFrame& consume) const;

 private:
  std::filesystem::path m_dir;
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
