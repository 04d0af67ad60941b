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

namespace pleat::cli {

namespace {

constexpr char kChunkMagic[8] = {'P', 'L', 'E', 'A', 'T', 'C', 'K', '1'};
constexpr char kChunkEnd[8] = {'P', 'L', 'E', 'A', 'T', 'E', 'N', 'D'};

// The header: magic, job key, chunk key, first and last frame.
struct ChunkHeader {
  std::array<char, 8> magic{};
  std::uint64_t job_key = 0, chunk_key = 0, first = 0, last = 0;
};
constexpr std::size_t kHeaderBytes = 8 + 4 * 8;
constexpr std::size_t kRecordBytes = 2 * 8;  // frame number, byte count

// The header at the start of `in` (all zero if it is shorter).
ChunkHeader read_header(std::istream& in) {
  std::string bytes(kHeaderBytes, '\0');
  in.read(bytes.data(), std::streamsize(bytes.size()));
  ChunkHeader header;
  if (!in) return header;
  ByteReader reader(bytes);
  header.magic = reader.get<std::array<char, 8>>();
  header.job_key = reader.get<std::uint64_t>(), header.chunk_key = reader.get<std::uint64_t>();
  header.first = reader.get<std::uint64_t>(), header.last = reader.get<std::uint64_t>();
  return header;
}

std::string chunk_name(std::size_t first, std::size_t last) {
  char name[96];
  std::snprintf(name, sizeof name, "chunk_%08zu_%08zu.pleatchunk", first, last);
  return name;
}

}  // namespace

Checkpoint::Checkpoint(std::filesystem::path dir, std::uint64_t job_key)
    : m_dir(std::move(dir)), m_job_key(job_key) {}

std::filesystem::path Checkpoint::path_of(std::size_t first, std::size_t last) const {
  return m_dir / chunk_name(first, last);
}

std::vector<bool> Checkpoint::scan(const std::vector<std::size_t>& bounds,
                                   const std::vector<std::uint64_t>& chunk_keys) {
  std::filesystem::create_directories(m_dir);
  std::map<std::string, std::size_t> wanted;
  for (std::size_t c = 0; c + 1 < bounds.size(); ++c) wanted[chunk_name(bounds[c], bounds[c + 1])] = c;
  std::vector<bool> kept(bounds.size() - 1, false);
  std::size_t stale = 0;
  for (const auto& entry : std::filesystem::directory_iterator(m_dir)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".pleatchunk" || name.rfind("chunk_", 0) != 0) continue;
    char end[8] = {};
    std::ifstream in(entry.path(), std::ios::binary);
    const ChunkHeader header = read_header(in);
    const auto size = entry.file_size();
    if (in && size >= kHeaderBytes + sizeof end) {
      in.seekg(std::streamoff(size - sizeof end));
      in.read(end, sizeof end);
    }
    const auto it = wanted.find(name);
    const bool valid = in && std::equal(kChunkMagic, kChunkMagic + 8, header.magic.begin()) &&
                       std::equal(kChunkEnd, kChunkEnd + 8, end) && header.job_key == m_job_key &&
                       it != wanted.end() && header.chunk_key == chunk_keys[it->second];
    if (valid) {
      kept[it->second] = true;
    } else {
      std::filesystem::remove(entry.path());
      ++stale;
    }
  }
  if (stale > 0)
    std::cerr << "pleat: checkpoint " << m_dir.string() << ": " << stale
              << " chunk file(s) of another input, plan or command removed (their key differs)\n";
  return kept;
}

void Checkpoint::read(std::size_t first, std::size_t last, const ConsumeFrame& consume) const {
  const std::filesystem::path path = path_of(first, last);
  auto unreadable = [&](const std::string& why) {
    return std::runtime_error(path.string() + ": checkpoint chunk unreadable: " + why);
  };
  std::error_code ec;
  const std::uintmax_t file_size = std::filesystem::file_size(path, ec);
  if (ec) throw unreadable(ec.message());
  std::ifstream in(path, std::ios::binary);
  const ChunkHeader header = read_header(in);
  if (!in) throw unreadable("no header");
  std::uintmax_t at = kHeaderBytes;  // bytes of the file read so far
  for (std::size_t f = header.first; f < header.last; ++f) {
    const std::string place = "frame " + std::to_string(f) + ", byte " + std::to_string(at);
    std::string record(kRecordBytes, '\0');
    in.read(record.data(), std::streamsize(record.size()));
    if (!in) throw unreadable(place + ": the file ends");
    at += kRecordBytes;
    ByteReader reader(record);
    const auto frame = reader.get<std::uint64_t>(), size = reader.get<std::uint64_t>();
    if (frame != f) throw unreadable(place + ": the record is of frame " + std::to_string(frame));
    if (size > file_size - at) throw unreadable(place + ": a record of " + std::to_string(size) + " bytes");
    std::string bytes(size, '\0');
    in.read(bytes.data(), std::streamsize(bytes.size()));
    if (!in) throw unreadable(place + ": the file ends");
    at += size;
    consume(f, bytes);
  }
}

ChunkFile::ChunkFile(const Checkpoint& checkpoint, std::size_t first, std::size_t last,
                     std::uint64_t chunk_key)
    : m_file(checkpoint.path_of(first, last)) {
  const std::string header = ByteWriter()
                                 .put(kChunkMagic)
                                 .put<std::uint64_t>(checkpoint.job_key())
                                 .put<std::uint64_t>(chunk_key)
                                 .put<std::uint64_t>(first)
                                 .put<std::uint64_t>(last)
                                 .take();
  m_file.stream().write(header.data(), std::streamsize(header.size()));
}

void ChunkFile::add(std::size_t frame, std::string_view bytes) {
  const std::string record = ByteWriter().put<std::uint64_t>(frame).put<std::uint64_t>(bytes.size()).take();
  m_file.stream().write(record.data(), std::streamsize(record.size()));
  m_file.stream().write(bytes.data(), std::streamsize(bytes.size()));
}

void ChunkFile::commit() {
  m_file.stream().write(kChunkEnd, sizeof kChunkEnd);
  m_file.commit();
}

}  // namespace pleat::cli
