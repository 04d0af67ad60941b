#include "cli/checkpoint.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>

namespace pleat::cli {

namespace {

constexpr char kChunkMagic[8] = {'P', 'L', 'E', 'A', 'T', 'C', 'K', '1'};
constexpr char kChunkEnd[8] = {'P', 'L', 'E', 'A', 'T', 'E', 'N', 'D'};

struct ChunkHeader {
  char magic[8];
  std::uint64_t job_key, chunk_key, first, last;
};

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
    ChunkHeader header{};
    char end[8] = {};
    std::ifstream in(entry.path(), std::ios::binary);
    in.read(reinterpret_cast<char*>(&header), sizeof header);
    const auto size = entry.file_size();
    if (in && size >= sizeof header + sizeof end) {
      in.seekg(std::streamoff(size - sizeof end));
      in.read(end, sizeof end);
    }
    const auto it = wanted.find(name);
    const bool valid = in && std::equal(kChunkMagic, kChunkMagic + 8, header.magic) &&
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
  std::ifstream in(path, std::ios::binary);
  ChunkHeader header{};
  in.read(reinterpret_cast<char*>(&header), sizeof header);
  for (std::size_t f = header.first; f < header.last && in; ++f) {
    std::uint64_t record[2] = {};
    in.read(reinterpret_cast<char*>(record), sizeof record);
    std::string bytes(record[1], '\0');
    in.read(bytes.data(), std::streamsize(bytes.size()));
    if (!in || record[0] != f) break;
    consume(f, bytes);
  }
  if (!in) throw std::runtime_error(path.string() + ": checkpoint chunk unreadable");
}

ChunkFile::ChunkFile(const Checkpoint& checkpoint, std::size_t first, std::size_t last,
                     std::uint64_t chunk_key)
    : m_file(checkpoint.path_of(first, last)) {
  ChunkHeader header{};
  std::copy(kChunkMagic, kChunkMagic + 8, header.magic);
  header.job_key = checkpoint.job_key(), header.chunk_key = chunk_key, header.first = first,
  header.last = last;
  m_file.stream().write(reinterpret_cast<const char*>(&header), sizeof header);
}

void ChunkFile::add(std::size_t frame, std::string_view bytes) {
  const std::uint64_t record[2] = {frame, bytes.size()};
  m_file.stream().write(reinterpret_cast<const char*>(record), sizeof record);
  m_file.stream().write(bytes.data(), std::streamsize(bytes.size()));
}

void ChunkFile::commit() {
  m_file.stream().write(kChunkEnd, sizeof kChunkEnd);
  m_file.commit();
}

}  // namespace pleat::cli
