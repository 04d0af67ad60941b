// The static engine's options (VisibilityParams) and the progress of a frame being computed (FrameProgress),
// read by both engines (visibility.hpp, kinetic/kinetic_visibility.hpp) and by the frame assembly.
// Thread safety: FrameProgress is advanced and read with relaxed atomics from any thread.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>

namespace pleat {

/// How far the frame being computed is, for progress reports within long frames: its planes (each frame has
/// its own: planes_for_frame), slices done (each plane's 2D cones), then receiving vertices whose 3D cones
/// are assembled (counted in steps of 64). The engines set and add to the counters with relaxed atomics (a
/// few per thousand vertices); the caller resets them between frames and may read them from any thread.
struct FrameProgress {
  std::atomic<std::size_t> planes{0};
  std::atomic<std::size_t> slices{0};
  std::atomic<std::size_t> vertices{0};
  void reset() {
    planes.store(0, std::memory_order_relaxed);
    slices.store(0, std::memory_order_relaxed);
    vertices.store(0, std::memory_order_relaxed);
  }
};

struct VisibilityParams {
  bool parallel = true;  ///< TBB-parallel over slices
  /// Called during a frame, from the thread that did the work, after each slice and every 256 assembled
  /// vertices: where a caller checks for an interrupt (the Python module: Ctrl+C). It may throw to abandon
  /// the frame; the exception leaves compute(), and the engine stays usable. Empty: not called.
  std::function<void()> poll = {};
  FrameProgress* progress = nullptr;  ///< when set, advanced as the frame is computed
};

}  // namespace pleat
