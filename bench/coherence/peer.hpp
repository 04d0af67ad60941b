// The peer: per-vertex ray casting with Embree (shading/ray_visibility), configured as its best user would.
//
// Per frame, timed: the BVH brought to the frame (refit or rebuild), vertex normals, K stratified
// cosine-weighted rays per vertex and side. Frame 0 builds the scene and is not timed. Directions are fixed
// per vertex and side across frames (the same seed every frame, so the noise does not flicker), or, for the
// "embree-random" row, drawn anew every frame (seed + frame), as a naive frame loop would.
//
// The configuration sweep (one thread, Options::sweep_rays rays, the measurement's frames) tries, greedily:
// every ray call (1M streams, 4/8/16-wide packets, single rays) on a refitted robust BVH; then the fastest
// with the coherent-rays hint; then without RTC_SCENE_FLAG_ROBUST; then with a rebuilt BVH per frame. Each
// step is kept when it is faster: judged by process CPU time per frame (median over the frames), the least of
// two runs of each candidate made in turn with the others of its step. The ladder then runs with the winner.
// Every configuration casts the same rays (tests/ray_visibility_test: EveryRayCallGivesTheSameAnswers),
// except that a non-robust BVH may let a ray through a shared edge: its error is measured like every other.
#pragma once

#include <string>
#include <vector>

#include "bench/coherence/measurement.hpp"
#include "shading/embree_scene.hpp"

namespace pleat::bench {

std::string describe(const EmbreeSceneParams& p);

/// Embree on `frames` (frame 0 untimed) with `rays` per vertex and side and `threads` TBB threads; keeps the
/// sky values of the timed frames when asked. Errors are reported in the row's status.
MethodRow run_embree(const MeshTopology& topology, const std::vector<Frame>& frames,
                     const EmbreeSceneParams& config, int rays, bool random_directions, int threads,
                     bool keep_sky);

/// The greedy sweep above; returns the fastest configuration and fills `trials` (fastest first).
EmbreeSceneParams fastest_peer(const MeshTopology& topology, const std::vector<Frame>& frames, int rays,
                               std::vector<PeerTrial>& trials);

/// The reference: `rays` per vertex and side (another seed), on every timed frame, every `stride`-th vertex
/// (the others NaN), robust BVH, all threads. Untimed.
std::vector<SkyValues> reference_sky(const MeshTopology& topology, const std::vector<Frame>& frames, int rays,
                                     Index stride);

}  // namespace pleat::bench
