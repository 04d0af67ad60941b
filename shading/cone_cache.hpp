// The cone cache (`.cones`): every frame's 3D visibility cones, so that lighting can change after the cones
// were computed (the paper's point: cones once, any lighting afterwards). `pleat visibility --cones` writes
// it, `pleat shade --cones` shades from it without computing any visibility.
//
// Format, version 3 (exact) or 4 (compact; the only difference: piece directions, below); versions 1 and 2,
// the same without checksums, are still read. Little-endian throughout; u32/u64 unsigned integers, f64
// IEEE-754 doubles (the engines' numbers exactly, so shading from the cache equals shading from freshly
// computed cones).
//   header
//     char[8]   magic "PLEATCNS"
//     u32       version (3 or 4; 1 or 2: no checksums)
//     u32       table_offset: byte offset of the frame table (= size of the header)
//     u32       V: vertices (welded, as the engines index them)
//     u32       I: vertices of the input, in its order
//     u32       T: triangles
//     u32       F: frames in the cache
//     u64       topology fingerprint: FNV-1a 64 over the triangles' welded vertex indices (u32 LE, in order)
//     f64       frames per second of the input (0 for a single frame)
//     u32       P, then char[P]: the slicing plan, as `pleat visibility` describes it (UTF-8)
//     u32[I]    welded vertex of each input vertex (the input's vertex order)
//     per frame: u32 input frame index, f64 time in seconds
//   frame table (at table_offset)
//     u64[F+1]  absolute byte offset of each frame block; the last one is the file size
//     u32[F]    (versions 3, 4) CRC-32 of each frame block (support/checksum.hpp)
//     u32       (versions 3, 4) CRC-32 of every byte before it: the header and the table
//   frame block (one per frame, in the table's order; readable without reading the ones before)
//     u64       positions fingerprint: FNV-1a 64 over the frame's vertex positions (f64 x, y, z LE)
//     f64[V][3] unit vertex normals
//     per side (front, back):
//       f64[V][5]  measures: sky visibility A, bent normal (x, y, z), solid angle
//       per vertex: u32 pieces; per piece: u32 n, then the n unit edge directions (radial order):
//         version 1: f64[n][3]; version 2: u16[n][2], octahedral coordinates (the direction's projection onto
//         the octahedron |x|+|y|+|z| = 1, the lower half folded over, each coordinate mapped from [-1, 1] to
//         0..65535), within 5e-5 radians of the engine's direction: 4 bytes instead of 24, the bulk of a
//         frame's block.
// Written as frames complete to a temporary file, renamed into place when the last frame is in (atomic: a
// failed run leaves no cache). Reading checks everything it reads (magic, version, the checksums, sizes
// against the file, the table, every count against its block, finite numbers) and throws InputError naming
// the file and the frame or byte; a checksum that does not match names the file as damaged.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "static_core/mesh.hpp"
#include "static_core/visibility_cone.hpp"

namespace pleat {

/// FNV-1a 64 over the triangles' vertex indices: a mesh's identity for the cone cache.
std::uint64_t topology_fingerprint(const MeshTopology& topology);
/// FNV-1a 64 over a frame's positions: which frame of which simulation the cones belong to.
std::uint64_t positions_fingerprint(const Frame& frame);

/// How a cone cache stores the directions of its cones' pieces (everything else is stored exactly).
enum class ConeEncoding {
  Exact,    ///< version 3 (1): the engines' doubles (shading from the cache equals shading from fresh cones)
  Compact,  ///< version 4 (2): 16-bit octahedral coordinates, within 5e-5 radians (about 3.5x smaller)
};
const char* cone_encoding_name(ConeEncoding encoding);  ///< "exact" or "compact"

/// What a cone cache says about the mesh, the plan and its frames.
struct ConeCacheHeader {
  ConeEncoding encoding = ConeEncoding::Exact;
  Index vertices = 0;
  std::size_t triangles = 0;
  std::uint64_t fingerprint = 0;
  double frame_rate = 0.0;
  std::string plan;
  std::vector<Index> welded_of_input;
  std::vector<std::uint32_t> frames;  ///< input frame index of each cached frame
  std::vector<double> times;          ///< seconds
};

/// One frame's block of the format above (positions fingerprint, normals, measures, cones), as add_frame
/// writes it: for a frame computed in another process (an MPI rank, a checkpointed chunk), encoded there and
/// added here with ConeCacheWriter::add_encoded_frame.
std::string encode_cone_frame(const Frame& frame, const FrameVisibility& visibility,
                              ConeEncoding encoding = ConeEncoding::Exact);

/// Streams a cone cache frame by frame; commit() after the last frame puts it in place.
class ConeCacheWriter {
 public:
  /// `frames`: the input frame indices that add_frame will receive, in order. Throws std::runtime_error
  /// naming the path when the file cannot be written.
  ConeCacheWriter(const std::filesystem::path& path, const MeshTopology& topology,
                  std::span<const Index> welded_of_input, double frame_rate, std::string plan,
                  std::vector<std::uint32_t> frames, ConeEncoding encoding = ConeEncoding::Exact);
  ~ConeCacheWriter();
  ConeCacheWriter(const ConeCacheWriter&) = delete;
  ConeCacheWriter& operator=(const ConeCacheWriter&) = delete;

  /// The next announced frame: its positions (for the fingerprint) and its cones.
  void add_frame(const Frame& frame, const FrameVisibility& visibility);
  /// The next announced frame as encode_cone_frame gave it (in this cache's encoding). Throws
  /// std::invalid_argument when the block is too short for the cache's vertex count.
  void add_encoded_frame(std::string_view block);
  /// Writes the frame table and its checksums and closes the file (AtomicFile::close). Every frame must have
  /// been added.
  void close();
  /// close(), then renames the file into place.
  void commit();

  struct Impl;

 private:
  std::unique_ptr<Impl> m_impl;
};

/// A cone cache opened for reading; frames are read on demand.
class ConeCacheReader {
 public:
  /// Reads and checks the header and the frame table (and their checksum). Throws InputError.
  explicit ConeCacheReader(const std::filesystem::path& path);
  ~ConeCacheReader();

  const ConeCacheHeader& header() const;
  /// Throws InputError unless the cache was computed for this mesh (vertex and triangle counts, triangles,
  /// the input's vertex order).
  void check_mesh(const MeshTopology& topology, std::span<const Index> welded_of_input) const;
  /// The cache's position of input frame `frame`; throws InputError when it is not cached.
  std::size_t index_of_frame(std::size_t frame) const;
  /// Reads cached frame `index` (a position in header().frames) into `out`, replacing its cones, measures and
  /// normals (stats are left empty). Throws InputError naming the frame and the byte where it is malformed
  /// or its checksum does not match, or when `frame` (the input's positions for it) is not the frame the
  /// cones were computed for.
  void read_frame(std::size_t index, const Frame& frame, FrameVisibility& out);
  /// The same for a reader that has no positions to check the frame against (the Python module's
  /// read_cone_cache, which reads the values only).
  void read_frame_unchecked(std::size_t index, FrameVisibility& out);

  struct Impl;

 private:
  std::unique_ptr<Impl> m_impl;
};

}  // namespace pleat
