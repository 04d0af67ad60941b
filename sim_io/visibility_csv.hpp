// The visibility CSV (docs/method.md §12, the contract outside checks read): the header
// `frame,vertex,front,back,source_frame`, then one row per frame and INPUT vertex (0-based, input order),
// front/back = A_front / A_back (docs/method.md §1), both empty for a vertex no triangle uses (it has no
// surface, so no visibility: CSV readers such as pandas read NaN), source_frame = the frame's number in the
// input (MeshSequence::source_frame: the PC2 scene frame, the number in an OBJ sequence's file name, ...).
//
// Values are written in the shortest decimal form that reads back to the same double (std::to_chars), so a
// CSV round-trips exactly. Results computed on welded vertices are mapped back to input vertices through
// MeshSequence::welded_of_input(). The writer streams frame by frame into an AtomicFile: O(V) memory, and
// nothing is left on disk unless commit() is reached.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "static_core/mesh.hpp"
#include "support/atomic_file.hpp"

namespace pleat {

class VisibilityCsvWriter {
 public:
  /// `welded_of_input` maps each input vertex to its welded vertex (MeshSequence::welded_of_input());
  /// `without_surface`: the welded vertices no triangle uses (mesh_report.hpp's isolated_vertices), whose
  /// values are left empty.
  VisibilityCsvWriter(const std::filesystem::path& path, std::vector<Index> welded_of_input,
                      const std::vector<Index>& without_surface = {});
  /// Appends the rows of one frame (its index and its source frame number); front/back hold one value per
  /// welded vertex. Throws std::runtime_error naming the file and the reason when a write failed.
  void add_frame(std::size_t frame, std::int64_t source_frame, const std::vector<double>& front,
                 const std::vector<double>& back);
  /// Writes out and closes the file (AtomicFile::close: throws std::runtime_error on I/O failure).
  void close();
  /// close(), then renames the file into place.
  void commit();

 private:
  std::vector<Index> m_welded_of_input;
  Index m_num_welded = 0;
  std::vector<char> m_without_surface;  ///< per welded vertex
  AtomicFile m_file;
};

struct VisibilityRow {
  std::size_t frame = 0;
  std::size_t vertex = 0;
  double front = 0.0;  ///< NaN for a vertex without surface (empty fields)
  double back = 0.0;
  std::int64_t source_frame = 0;
};

/// Reads a visibility CSV (for tests and comparisons). Throws InputError(path, "line N") on a wrong header,
/// a malformed row or a value that is not a finite number (both empty: NaN, a vertex without surface).
std::vector<VisibilityRow> read_visibility_csv(const std::filesystem::path& path);

}  // namespace pleat
