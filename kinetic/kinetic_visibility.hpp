// KineticVisibility: the cones of a cloth sequence, frame after frame, with every slicing plane's structure
// kept alive between frames (docs/method.md §11; Stewart 1999 §6 names this as future work).
//
// Built from the topology, a slicing plan (fixed for the sequence) and the first frame (a static build).
// advance(next) keeps every slice the frame's motion does not reach and every vertex whose 3D cone's inputs
// did not change (docs/method.md §11.6, kinetic/internal/change_tracking.hpp), and carries every reached
// slice to the next frame (kinetic_slice.hpp): the mesh vertices that cross a plane are applied as local
// edits of its chains, the kept triangulation is certified at the new frame with exact predicates, and the
// slice vertices of failed certificates are taken out and put back; where that would cost more than a
// rebuild, or the slice degenerates, it is rebuilt. The cones are then grown on the kept structure and merged
// by the same code as the static engine (static_core/frame_assembly.hpp): the output equals a full static
// recompute of the same frame (tests/kinetic_visibility_test.cpp proves it on random motions). Slices are
// independent and processed in parallel (TBB). `topology` must outlive the engine. The constructor validates
// the topology and the first frame, advance() each frame (static_core/mesh_validation.hpp: InputError; a
// rejected frame leaves the engine as it was).
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <memory>

#include "kinetic/kinetic_policy.hpp"
#include "static_core/mesh.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility.hpp"
#include "static_core/visibility_cone.hpp"

namespace pleat {
namespace kinetic {
class KineticSlice;
struct KineticInspect;
}  // namespace kinetic

struct KineticParams {
  bool parallel = true;           ///< TBB-parallel over slices and vertices
  kinetic::KineticPolicy policy;  ///< repair or rebuild
  /// Check every slice's invariants after each interval (KineticSlice::check_invariants, exact); a violation
  /// throws InvariantError. On in Debug builds.
#ifdef NDEBUG
  bool check_invariants = false;
#else
  bool check_invariants = true;
#endif
  /// As VisibilityParams::poll. An exception it throws abandons the frame and leaves the slices between
  /// two frames: build a new engine (pleat::Engine does) before the next frame.
  std::function<void()> poll = {};
  FrameProgress* progress = nullptr;  ///< when set, advanced as each frame is computed (visibility.hpp)
};

class KineticVisibility {
 public:
  KineticVisibility(const MeshTopology& topology, SlicingPlan plan, const Frame& first,
                    const KineticParams& params = {});
  ~KineticVisibility();
  KineticVisibility(KineticVisibility&&) noexcept;
  KineticVisibility& operator=(KineticVisibility&&) noexcept;

  /// The cones of the current frame (the first one after construction).
  const FrameVisibility& current() const;
  /// Moves to `next` (same topology) and returns its cones; the reference stays valid until the next call.
  /// Costs in proportion to what changed (docs/method.md §11.6): a frame whose positions equal the previous
  /// frame's bit for bit (a held frame) costs O(V), its cones are the previous ones; otherwise only the
  /// slices the moved vertices reach are carried (the others keep their slice, triangulation and cones), and
  /// only the vertices whose offers, fan or fill source changed get their 3D cones assembled again.
  const FrameVisibility& advance(const Frame& next);
  /// What the last advance() did (zeros after construction).
  const KineticFrameStats& last_stats() const;
  const SlicingPlan& plan() const;

 private:
  friend struct kinetic::KineticInspect;  // the kept state, for tests (kinetic/internal/kinetic_inspect.hpp)
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace pleat
