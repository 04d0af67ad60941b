#include "cli/checkpoint.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>

#include "support/byte_stream.hpp"
#include "support/checksum.hpp"

namespace pleat::cli {

namespace {

constexpr char kChunkMagic[8] = {'P', 'L', 'E', 'A', 'T', 'C', 'K', '2'};
constexpr char kOldChunkMagic[8] = {'P', 'L', 'E', 'A', 'T', 'C', 'K', '1'};  // without checksums
constexpr char kChunkEnd[8] = {'P', 'L', 'E', 'A', 'T', 'E', 'N', 'D'};
constexpr std::size_t kHeaderBytes = 8 + 3 * 8 + 4;  // magic, key, first, last, the header's CRC-32
constexpr std::size_t kRecordBytes = 2 * 8 + 4;      // frame number, byte count, the bytes' CRC-32

std::string chunk_name(std::size_t first, std::size_t last) {
  char name[96];
  std::snprintf(name, sizeof name, "chunk_%08zu_%08zu.pleatchunk", first, last);
  return name;
}

// What a chunk file holds for the job: its frames whole (Good), another job's (Foreign: another key, or a
// chunk of an earlier pleat), or damage (`why` says what and where).
enum class ChunkState { Good, Foreign, Damaged };
struct ChunkCheck {
  ChunkState state = ChunkState::Good;
  std::string why;
};

// Reads the chunk file `path` for frames [first, last) and key `key`, checking every checksum, and passes
// each frame's bytes to `consume` (when given). O(file size); allocates at most what the file holds.
ChunkCheck walk_chunk(const std::filesystem::path& path, std::size_t first, std::size_t last,
                      std::uint64_t key, const ConsumeFrame* consume) {
  const auto damaged = [](const std::string& why) { return ChunkCheck{ChunkState::Damaged, why}; };
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  std::ifstream in(path, std::ios::binary);
  if (ec || !in) return damaged("cannot be read");
  std::string header(kHeaderBytes, '\0');
  in.read(header.data(), std::streamsize(header.size()));
  if (!in) return damaged("truncated: " + std::to_string(size) + " bytes, shorter than its header");
  ByteReader reader(header);
  const auto magic = reader.get<std::array<char, 8>>();
  if (std::equal(kOldChunkMagic, kOldChunkMagic + 8, magic.begin())) return {ChunkState::Foreign, ""};
  if (!std::equal(kChunkMagic, kChunkMagic + 8, magic.begin())) return damaged("byte 0: no chunk magic");
  const auto chunk_key = reader.get<std::uint64_t>();
  const auto range_first = reader.get<std::uint64_t>(), range_last = reader.get<std::uint64_t>();
  if (reader.get<std::uint32_t>() != checksum(std::string_view(header).substr(0, kHeaderBytes - 4)))
    return damaged("bytes 0-" + std::to_string(kHeaderBytes - 1) + ": the header's checksum does not match");
  if (chunk_key != key || range_first != first || range_last != last) return {ChunkState::Foreign, ""};
  std::uintmax_t at = kHeaderBytes;  // bytes of the file read so far
  for (std::size_t f = first; f < last; ++f) {
    const std::string place = "frame " + std::to_string(f) + ", byte " + std::to_string(at);
    std::string record(kRecordBytes, '\0');
    in.read(record.data(), std::streamsize(record.size()));
    if (!in) return damaged(place + ": truncated (the file ends)");
    at += kRecordBytes;
    ByteReader fields(record);
    const auto frame = fields.get<std::uint64_t>(), bytes = fields.get<std::uint64_t>();
    const auto sum = fields.get<std::uint32_t>();
    if (frame != f) return damaged(place + ": the record is of frame " + std::to_string(frame));
    if (bytes > size - at)
      return damaged(place + ": truncated or damaged, a record of " + std::to_string(bytes) +
                     " bytes, past the end of the file");
    std::string payload(bytes, '\0');
    in.read(payload.data(), std::streamsize(payload.size()));
    if (!in) return damaged(place + ": truncated (the file ends)");
    if (checksum(payload) != sum) return damaged(place + ": the frame's checksum does not match");
    at += bytes;
    if (consume) (*consume)(f, payload);
  }
  char end[8] = {};
  in.read(end, sizeof end);
  if (!in || !std::equal(kChunkEnd, kChunkEnd + 8, end) || at + sizeof end != size)
    return damaged("byte " + std::to_string(at) + ": no end marker where the frames end");
  return {};
}

}  // namespace

Checkpoint::Checkpoint(std::filesystem::path dir) : m_dir(std::move(dir)) {}

std::filesystem::path Checkpoint::path_of(std::size_t first, std::size_t last) const {
  return m_dir / chunk_name(first, last);
}

std::vector<bool> Checkpoint::scan(const std::vector<std::size_t>& bounds,
                                   const std::vector<std::uint64_t>& chunk_keys) {
  std::filesystem::create_directories(m_dir);
  remove_stale_temporaries(m_dir);
  std::vector<bool> kept(bounds.size() - 1, false);
  std::size_t foreign = 0;
  for (std::size_t c = 0; c + 1 < bounds.size(); ++c) {
    const std::filesystem::path path = path_of(bounds[c], bounds[c + 1]);
    std::error_code ec;
    if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec))) continue;
    const ChunkCheck check = walk_chunk(path, bounds[c], bounds[c + 1], chunk_keys[c], nullptr);
    if (check.state == ChunkState::Good) {
      kept[c] = true;
      continue;
    }
    std::filesystem::remove(path);
    if (check.state == ChunkState::Foreign)
      ++foreign;
    else
      std::cerr << "pleat: checkpoint " << m_dir.string() << ": " << path.filename().string()
                << " is damaged (" << check.why << "); it is computed again\n";
  }
  if (foreign > 0)
    std::cerr << "pleat: checkpoint " << m_dir.string() << ": " << foreign
              << " chunk file(s) of another input, plan or command removed (their key differs)\n";
  return kept;
}

void Checkpoint::read(std::size_t first, std::size_t last, std::uint64_t chunk_key,
                      const ConsumeFrame& consume) const {
  const std::filesystem::path path = path_of(first, last);
  const ChunkCheck check = walk_chunk(path, first, last, chunk_key, &consume);
  if (check.state == ChunkState::Foreign)
    throw std::runtime_error(path.string() +
                             ": checkpoint chunk replaced by another job's while this one ran");
  if (check.state == ChunkState::Damaged)
    throw std::runtime_error(path.string() + ": checkpoint chunk damaged: " + check.why);
}

ChunkFile::ChunkFile(const Checkpoint& checkpoint, std::size_t first, std::size_t last,
                     std::uint64_t chunk_key)
    : m_file(checkpoint.path_of(first, last)) {
  std::string header = ByteWriter()
                           .put(kChunkMagic)
                           .put<std::uint64_t>(chunk_key)
                           .put<std::uint64_t>(first)
                           .put<std::uint64_t>(last)
                           .take();
  header += ByteWriter().put<std::uint32_t>(checksum(header)).take();
  m_file.stream().write(header.data(), std::streamsize(header.size()));
}

void ChunkFile::add(std::size_t frame, std::string_view bytes) {
  const std::string record = ByteWriter()
                                 .put<std::uint64_t>(frame)
                                 .put<std::uint64_t>(bytes.size())
                                 .put<std::uint32_t>(checksum(bytes))
                                 .take();
  m_file.stream().write(record.data(), std::streamsize(record.size()));
  m_file.stream().write(bytes.data(), std::streamsize(bytes.size()));
  m_file.check();
}

void ChunkFile::commit() {
  m_file.stream().write(kChunkEnd, sizeof kChunkEnd);
  m_file.commit();
}

}  // namespace pleat::cli
