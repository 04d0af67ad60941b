// render: PNG images of the shaded cloth, made by casting primary rays with Embree, so a user can look at
// pleat's output without another program (`pleat shade --render DIR`).
//
// Each pixel averages 2×2 stratified samples (anti-aliasing). A sample that hits triangle t interpolates
// the vertex colours of t barycentrically; the back colours are used when the ray meets the face from
// behind (ray · N > 0, N = (p1−p0) × (p2−p0) in the input winding), so the inside of a sleeve shows its own
// shading. Colours are given in sRGB, interpolated and averaged in linear light, and encoded back to 8-bit
// sRGB. Unlit: the colours are the shading. Misses show a neutral vertical grey gradient.
// Cost: width × height × 4 primary rays, TBB-parallel over rows,
// plus one BVH build. Files are written atomically (temporary sibling, then rename).
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/ext/vector_uint3_sized.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shading/embree_scene.hpp"
#include "static_core/mesh.hpp"

namespace pleat {

/// A pinhole camera. `up` need not be orthogonal to the view direction (it must not be parallel to it).
struct Camera {
  glm::dvec3 eye{0.0, 0.0, 3.0};
  glm::dvec3 target{0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  double fov_y_degrees = 35.0;  ///< vertical field of view
};

/// Parses "ex,ey,ez,tx,ty,tz,ux,uy,uz[,fov]" (the CLI's --camera). Throws std::invalid_argument naming
/// the offending field on malformed text, a zero view direction, or up parallel to the view.
Camera parse_camera(std::string_view text);

struct AutoFrameParams {
  glm::dvec3 up{0.0, 1.0, 0.0};  ///< world up (Blender's native data is Z-up: pass {0,0,1})
  /// Direction from the target towards the camera before the 3/4 turn; zero = automatic: the axis ⊥ up
  /// along which the bounds are thinnest (a hanging cloth is seen face on), positive sense.
  glm::dvec3 front{0.0};
  double azimuth_degrees = 30.0;    ///< turn about up, from `front`
  double elevation_degrees = 20.0;  ///< above the horizontal plane
  double fov_y_degrees = 35.0;
  double aspect = 4.0 / 3.0;  ///< width / height of the image to fit
  double margin = 1.05;       ///< > 1 leaves a border around the bounding sphere
};

/// A 3/4 view that fits the bounding sphere of `bounds` (a frame, or a whole sequence so the camera stays
/// put while the cloth moves) in the image. Throws std::invalid_argument on empty bounds.
/// A camera that frames `bounds` (one frame's, or a whole sequence's: MeshSequence::bounds). Throws
/// std::invalid_argument when the box is empty.
Camera auto_frame(const Bounds& bounds, const AutoFrameParams& params = {});
Camera auto_frame(const Frame& frame, const AutoFrameParams& params = {});

/// An 8-bit sRGB image, rows from the top, 3 bytes per pixel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;

  Image() = default;
  Image(int w, int h, glm::u8vec3 fill = {0, 0, 0});
  glm::u8vec3 pixel(int x, int y) const;
  void set_pixel(int x, int y, glm::u8vec3 c);
};

struct RenderParams {
  int samples_per_axis = 2;  ///< n×n stratified samples per pixel
  bool parallel = true;      ///< TBB over rows
};

/// Renders `frame` with an Embree scene that already holds it (reuse one scene across a sequence).
/// front_srgb / back_srgb: one sRGB colour in [0,1] per vertex. Throws InputError on an invalid frame
/// (static_core/mesh_validation.hpp; the one-shot forms below also check the topology), std::invalid_argument
/// on colour or image sizes.
Image render_image(const EmbreeScene& scene, const Frame& frame, std::span<const glm::vec3> front_srgb,
                   std::span<const glm::vec3> back_srgb, const Camera& camera, int width, int height,
                   const RenderParams& params = {});
/// One-shot: builds the scene, renders, returns the image.
Image render_image(const MeshTopology& topology, const Frame& frame, std::span<const glm::vec3> front_srgb,
                   std::span<const glm::vec3> back_srgb, const Camera& camera, int width, int height,
                   const RenderParams& params = {});

/// The PNG file of `image` (stb_image_write), in memory. Throws std::invalid_argument on a malformed image.
std::string encode_png(const Image& image);

/// Writes a PNG atomically. Throws std::runtime_error naming the path on failure.
void write_png(const std::filesystem::path& path, const Image& image);

/// render_image then write_png.
void render_png(const std::filesystem::path& path, const MeshTopology& topology, const Frame& frame,
                const std::vector<glm::vec3>& front_srgb, const std::vector<glm::vec3>& back_srgb,
                const Camera& camera, int width, int height);

/// `count` images of one frame, the camera turned about the axis through its target along its up vector
/// by 360°·i/count, in memory.
std::vector<Image> turntable_images(const MeshTopology& topology, const Frame& frame,
                                    const std::vector<glm::vec3>& front_srgb,
                                    const std::vector<glm::vec3>& back_srgb, const Camera& camera, int count,
                                    int width, int height);

/// turntable_images, written as DIRECTORY/STEM_000.png, ... Returns the paths written.
std::vector<std::filesystem::path> render_turntable(const std::filesystem::path& directory,
                                                    const std::string& stem, const MeshTopology& topology,
                                                    const Frame& frame,
                                                    const std::vector<glm::vec3>& front_srgb,
                                                    const std::vector<glm::vec3>& back_srgb,
                                                    const Camera& camera, int count, int width, int height);

/// Camera `camera` turned by `degrees` about the vertical axis through its target (along camera.up).
Camera orbit(const Camera& camera, double degrees);

/// Draws `text` with the built-in 5×7 bitmap font (A–Z, 0–9, . , : - _ ( ) / % = + ?; lower case is drawn
/// as upper case, anything else as '?'), top-left at (x, y), each font pixel `scale` pixels wide.
/// Clipped to the image.
void draw_text(Image& image, int x, int y, std::string_view text, glm::u8vec3 colour, int scale = 2);
/// Width in pixels of `text` drawn at `scale`.
int text_width(std::string_view text, int scale = 2);

struct LabeledImage {
  const Image* image = nullptr;
  std::string label;
};
/// Viridis (matplotlib's perceptually uniform colour map, dark blue to yellow), sampled at 9 stops, in sRGB;
/// t in [0, 1] (clamped).
glm::vec3 viridis(double t);

/// `image` with a legend appended under it: a viridis bar from `lo` to `hi` with its ends' and middle's
/// values, and `title` under it.
Image with_legend(const Image& image, double lo, double hi, std::string_view title);

/// Panels side by side, each under a dark label bar, separated by a thin gap; panels of different heights
/// are top-aligned on the background.
Image side_by_side(std::span<const LabeledImage> panels);

}  // namespace pleat
