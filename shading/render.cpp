// render: camera helpers, Embree primary rays, PNG output, turntables, labelled side-by-side panels.
#include "shading/render.hpp"

#include <stb/stb_image_write.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <glm/glm.hpp>
#include <numbers>
#include <stdexcept>

#include "static_core/mesh_validation.hpp"
#include "support/atomic_file.hpp"
#include "support/srgb.hpp"

namespace pleat {

namespace {

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

std::uint8_t to_byte(double srgb) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(srgb, 0.0, 1.0) * 255.0));
}

/// Neutral background: light grey at the top to mid grey at the bottom (sRGB), returned in linear light.
glm::dvec3 background(double v) {
  const double srgb = 0.80 + (0.46 - 0.80) * v;
  return glm::dvec3(srgb_to_linear(srgb));
}

void validate_colours(std::size_t vertices, std::span<const glm::vec3> front,
                      std::span<const glm::vec3> back) {
  if (front.size() != vertices || back.size() != vertices)
    throw std::invalid_argument("render: " + std::to_string(front.size()) + " front and " +
                                std::to_string(back.size()) + " back colours for " +
                                std::to_string(vertices) + " vertices");
}

// ---- 5×7 bitmap font: 7 rows per glyph, 5 bits per row, bit 4 = leftmost column. ----
struct Glyph {
  char c;
  std::array<std::uint8_t, 7> rows;
};

constexpr std::uint8_t b(const char* s) {
  std::uint8_t v = 0;
  for (int i = 0; i < 5; ++i) v = static_cast<std::uint8_t>((v << 1) | (s[i] == '1' ? 1 : 0));
  return v;
}

#define PLEAT_GLYPH(ch, r0, r1, r2, r3, r4, r5, r6)         \
  Glyph {                                                   \
    ch, { b(r0), b(r1), b(r2), b(r3), b(r4), b(r5), b(r6) } \
  }

const std::array kFont = {
    PLEAT_GLYPH(' ', "00000", "00000", "00000", "00000", "00000", "00000", "00000"),
    PLEAT_GLYPH('A', "01110", "10001", "10001", "11111", "10001", "10001", "10001"),
    PLEAT_GLYPH('B', "11110", "10001", "10001", "11110", "10001", "10001", "11110"),
    PLEAT_GLYPH('C', "01110", "10001", "10000", "10000", "10000", "10001", "01110"),
    PLEAT_GLYPH('D', "11110", "10001", "10001", "10001", "10001", "10001", "11110"),
    PLEAT_GLYPH('E', "11111", "10000", "10000", "11110", "10000", "10000", "11111"),
    PLEAT_GLYPH('F', "11111", "10000", "10000", "11110", "10000", "10000", "10000"),
    PLEAT_GLYPH('G', "01110", "10001", "10000", "10111", "10001", "10001", "01111"),
    PLEAT_GLYPH('H', "10001", "10001", "10001", "11111", "10001", "10001", "10001"),
    PLEAT_GLYPH('I', "01110", "00100", "00100", "00100", "00100", "00100", "01110"),
    PLEAT_GLYPH('J', "00111", "00010", "00010", "00010", "00010", "10010", "01100"),
    PLEAT_GLYPH('K', "10001", "10010", "10100", "11000", "10100", "10010", "10001"),
    PLEAT_GLYPH('L', "10000", "10000", "10000", "10000", "10000", "10000", "11111"),
    PLEAT_GLYPH('M', "10001", "11011", "10101", "10101", "10001", "10001", "10001"),
    PLEAT_GLYPH('N', "10001", "10001", "11001", "10101", "10011", "10001", "10001"),
    PLEAT_GLYPH('O', "01110", "10001", "10001", "10001", "10001", "10001", "01110"),
    PLEAT_GLYPH('P', "11110", "10001", "10001", "11110", "10000", "10000", "10000"),
    PLEAT_GLYPH('Q', "01110", "10001", "10001", "10001", "10101", "10010", "01101"),
    PLEAT_GLYPH('R', "11110", "10001", "10001", "11110", "10100", "10010", "10001"),
    PLEAT_GLYPH('S', "01111", "10000", "10000", "01110", "00001", "00001", "11110"),
    PLEAT_GLYPH('T', "11111", "00100", "00100", "00100", "00100", "00100", "00100"),
    PLEAT_GLYPH('U', "10001", "10001", "10001", "10001", "10001", "10001", "01110"),
    PLEAT_GLYPH('V', "10001", "10001", "10001", "10001", "10001", "01010", "00100"),
    PLEAT_GLYPH('W', "10001", "10001", "10001", "10101", "10101", "10101", "01010"),
    PLEAT_GLYPH('X', "10001", "10001", "01010", "00100", "01010", "10001", "10001"),
    PLEAT_GLYPH('Y', "10001", "10001", "01010", "00100", "00100", "00100", "00100"),
    PLEAT_GLYPH('Z', "11111", "00001", "00010", "00100", "01000", "10000", "11111"),
    PLEAT_GLYPH('0', "01110", "10001", "10011", "10101", "11001", "10001", "01110"),
    PLEAT_GLYPH('1', "00100", "01100", "00100", "00100", "00100", "00100", "01110"),
    PLEAT_GLYPH('2', "01110", "10001", "00001", "00010", "00100", "01000", "11111"),
    PLEAT_GLYPH('3', "11111", "00010", "00100", "00010", "00001", "10001", "01110"),
    PLEAT_GLYPH('4', "00010", "00110", "01010", "10010", "11111", "00010", "00010"),
    PLEAT_GLYPH('5', "11111", "10000", "11110", "00001", "00001", "10001", "01110"),
    PLEAT_GLYPH('6', "00110", "01000", "10000", "11110", "10001", "10001", "01110"),
    PLEAT_GLYPH('7', "11111", "00001", "00010", "00100", "01000", "01000", "01000"),
    PLEAT_GLYPH('8', "01110", "10001", "10001", "01110", "10001", "10001", "01110"),
    PLEAT_GLYPH('9', "01110", "10001", "10001", "01111", "00001", "00010", "01100"),
    PLEAT_GLYPH('.', "00000", "00000", "00000", "00000", "00000", "01100", "01100"),
    PLEAT_GLYPH(',', "00000", "00000", "00000", "00000", "01100", "00100", "01000"),
    PLEAT_GLYPH(':', "00000", "01100", "01100", "00000", "01100", "01100", "00000"),
    PLEAT_GLYPH('-', "00000", "00000", "00000", "11111", "00000", "00000", "00000"),
    PLEAT_GLYPH('_', "00000", "00000", "00000", "00000", "00000", "00000", "11111"),
    PLEAT_GLYPH('(', "00010", "00100", "01000", "01000", "01000", "00100", "00010"),
    PLEAT_GLYPH(')', "01000", "00100", "00010", "00010", "00010", "00100", "01000"),
    PLEAT_GLYPH('/', "00001", "00001", "00010", "00100", "01000", "10000", "10000"),
    PLEAT_GLYPH('%', "11000", "11001", "00010", "00100", "01000", "10011", "00011"),
    PLEAT_GLYPH('=', "00000", "00000", "11111", "00000", "11111", "00000", "00000"),
    PLEAT_GLYPH('+', "00000", "00100", "00100", "11111", "00100", "00100", "00000"),
    PLEAT_GLYPH('?', "01110", "10001", "00001", "00010", "00100", "00000", "00100"),
};
#undef PLEAT_GLYPH

const Glyph& glyph(char c) {
  if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  for (const Glyph& g : kFont)
    if (g.c == c) return g;
  return kFont.back();  // '?'
}

constexpr int kGlyphAdvance = 6;  // 5 columns + 1 of spacing

}  // namespace

// ---------------------------------------------------------------------------------------------- camera

Camera parse_camera(std::string_view text) {
  std::vector<double> values;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    std::string_view field = text.substr(start, comma - start);
    while (!field.empty() && field.front() == ' ') field.remove_prefix(1);
    while (!field.empty() && field.back() == ' ') field.remove_suffix(1);
    double value = 0.0;
    const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (field.empty() || error != std::errc() || end != field.data() + field.size() || !std::isfinite(value))
      throw std::invalid_argument("--camera: field " + std::to_string(values.size() + 1) + " ('" +
                                  std::string(field) +
                                  "') is not a number; expected ex,ey,ez,tx,ty,tz,ux,uy,uz[,fov]");
    values.push_back(value);
    start = comma + 1;
  }
  if (values.size() != 9 && values.size() != 10)
    throw std::invalid_argument(
        "--camera: expected 9 or 10 numbers (ex,ey,ez,tx,ty,tz,ux,uy,uz[,fov]), got " +
        std::to_string(values.size()));
  Camera camera;
  camera.eye = {values[0], values[1], values[2]};
  camera.target = {values[3], values[4], values[5]};
  camera.up = {values[6], values[7], values[8]};
  if (values.size() == 10) camera.fov_y_degrees = values[9];
  const glm::dvec3 view = camera.target - camera.eye;
  if (glm::length(view) == 0.0) throw std::invalid_argument("--camera: eye and target coincide");
  if (glm::length(glm::cross(view, camera.up)) <= 1e-12 * glm::length(view) * glm::length(camera.up))
    throw std::invalid_argument("--camera: up is parallel to the view direction (or zero)");
  if (!(camera.fov_y_degrees > 0.0 && camera.fov_y_degrees < 180.0))
    throw std::invalid_argument("--camera: fov must be in (0, 180) degrees");
  return camera;
}

Camera auto_frame(const Bounds& bounds, const AutoFrameParams& params) {
  if (bounds.empty()) throw std::invalid_argument("auto_frame: empty bounds");
  const glm::dvec3 up = glm::normalize(params.up);
  const glm::dvec3 centre = 0.5 * (bounds.lo + bounds.hi);
  const double radius = std::max(0.5 * glm::length(bounds.hi - bounds.lo), 1e-9);

  glm::dvec3 front = params.front;
  if (glm::length(front) == 0.0) {
    // The axis ⊥ up (most orthogonal) along which the bounds are thinnest.
    const glm::dvec3 extent = bounds.hi - bounds.lo;
    double best = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
      glm::dvec3 e(0.0);
      e[axis] = 1.0;
      if (std::abs(glm::dot(e, up)) > 0.5) continue;
      if (extent[axis] < best) {
        best = extent[axis];
        front = e;
      }
    }
  }
  front -= glm::dot(front, up) * up;  // horizontal
  if (glm::length(front) < 1e-12) front = std::abs(up.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  front -= glm::dot(front, up) * up;
  front = glm::normalize(front);
  const glm::dvec3 side = glm::cross(up, front);

  const double az = radians(params.azimuth_degrees), el = radians(params.elevation_degrees);
  const glm::dvec3 towards_eye =
      std::cos(el) * (std::cos(az) * front + std::sin(az) * side) + std::sin(el) * up;
  const double half_y = radians(params.fov_y_degrees) / 2.0;
  const double half_x = std::atan(std::tan(half_y) * params.aspect);
  const double distance = radius * params.margin / std::sin(std::min(half_x, half_y));

  Camera camera;
  camera.target = centre;
  camera.eye = centre + distance * towards_eye;
  camera.up = up;
  camera.fov_y_degrees = params.fov_y_degrees;
  return camera;
}

Camera auto_frame(const Frame& frame, const AutoFrameParams& params) {
  Bounds bounds;
  for (const glm::dvec3& p : frame.positions) bounds.add(p);
  return auto_frame(bounds, params);
}

Camera orbit(const Camera& camera, double degrees) {
  const glm::dvec3 axis = glm::normalize(camera.up);
  const glm::dvec3 r = camera.eye - camera.target;
  const double a = radians(degrees);
  // Rodrigues' rotation of r about axis.
  const glm::dvec3 rotated =
      r * std::cos(a) + glm::cross(axis, r) * std::sin(a) + axis * glm::dot(axis, r) * (1.0 - std::cos(a));
  Camera out = camera;
  out.eye = camera.target + rotated;
  return out;
}

// ---------------------------------------------------------------------------------------------- image

Image::Image(int w, int h, glm::u8vec3 fill) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3) {
  for (std::size_t i = 0; i < rgb.size(); i += 3) {
    rgb[i] = fill.r;
    rgb[i + 1] = fill.g;
    rgb[i + 2] = fill.b;
  }
}

glm::u8vec3 Image::pixel(int x, int y) const {
  const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

void Image::set_pixel(int x, int y, glm::u8vec3 c) {
  const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
  rgb[i] = c.r;
  rgb[i + 1] = c.g;
  rgb[i + 2] = c.b;
}

// ---------------------------------------------------------------------------------------------- rendering

Image render_image(const EmbreeScene& scene, const Frame& frame, std::span<const glm::vec3> front_srgb,
                   std::span<const glm::vec3> back_srgb, const Camera& camera, int width, int height,
                   const RenderParams& params) {
  const MeshTopology& topology = scene.topology();
  validate_frame(topology, frame, "render_image");
  validate_colours(topology.num_vertices, front_srgb, back_srgb);
  if (width < 1 || height < 1) throw std::invalid_argument("render: image size must be positive");
  const int n = std::max(1, params.samples_per_axis);

  // Vertex colours in linear light, once.
  std::array<std::vector<glm::dvec3>, 2> linear;
  for (int s = 0; s < 2; ++s) {
    const std::span<const glm::vec3> src = s == 0 ? front_srgb : back_srgb;
    linear[s].resize(src.size());
    for (std::size_t i = 0; i < src.size(); ++i)
      linear[s][i] = {srgb_to_linear(src[i].x), srgb_to_linear(src[i].y), srgb_to_linear(src[i].z)};
  }

  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::dvec3 true_up = glm::cross(right, forward);
  const double tan_y = std::tan(radians(camera.fov_y_degrees) / 2.0);
  const double tan_x = tan_y * static_cast<double>(width) / height;

  Image image(width, height);
  auto rows = [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < width; ++x) {
        glm::dvec3 sum(0.0);
        for (int sy = 0; sy < n; ++sy)
          for (int sx = 0; sx < n; ++sx) {
            const double px = (x + (sx + 0.5) / n) / width;   // [0,1) left to right
            const double py = (y + (sy + 0.5) / n) / height;  // [0,1) top to bottom
            RayQuery ray;
            ray.origin = camera.eye;
            ray.direction = forward + (2.0 * px - 1.0) * tan_x * right + (1.0 - 2.0 * py) * tan_y * true_up;
            const RayHit hit = scene.intersect(ray);
            if (!hit.hit) {
              sum += background(py);
              continue;
            }
            const Triangle& t = topology.triangles[hit.triangle];
            const glm::dvec3& p0 = frame.positions[t[0]];
            const glm::dvec3 normal = glm::cross(frame.positions[t[1]] - p0, frame.positions[t[2]] - p0);
            const int side = glm::dot(ray.direction, normal) > 0.0 ? 1 : 0;
            const std::vector<glm::dvec3>& c = linear[side];
            sum += (1.0 - hit.u - hit.v) * c[t[0]] + hit.u * c[t[1]] + hit.v * c[t[2]];
          }
        sum /= static_cast<double>(n * n);
        image.set_pixel(
            x, y,
            {to_byte(linear_to_srgb(sum.x)), to_byte(linear_to_srgb(sum.y)), to_byte(linear_to_srgb(sum.z))});
      }
  };
  if (params.parallel)
    tbb::parallel_for(tbb::blocked_range<int>(0, height, 4),
                      [&](const tbb::blocked_range<int>& r) { rows(r.begin(), r.end()); });
  else
    rows(0, height);
  return image;
}

Image render_image(const MeshTopology& topology, const Frame& frame, std::span<const glm::vec3> front_srgb,
                   std::span<const glm::vec3> back_srgb, const Camera& camera, int width, int height,
                   const RenderParams& params) {
  validate_mesh(topology, frame, "render_image");
  validate_colours(topology.num_vertices, front_srgb, back_srgb);
  EmbreeSceneParams scene_params;
  scene_params.mode = EmbreeSceneParams::BuildMode::Rebuild;
  scene_params.robust = false;
  const EmbreeScene scene(topology, frame, scene_params);
  return render_image(scene, frame, front_srgb, back_srgb, camera, width, height, params);
}

std::string encode_png(const Image& image) {
  if (image.width < 1 || image.height < 1 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3)
    throw std::invalid_argument("encode_png: malformed image");
  std::string bytes;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                               static_cast<std::size_t>(size));
  };
  if (stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, image.rgb.data(),
                             image.width * 3) == 0)
    throw std::runtime_error("PNG encoding failed");
  return bytes;
}

void write_png(const std::filesystem::path& path, const Image& image) {
  std::string bytes;
  try {
    bytes = encode_png(image);
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument("write_png: " + path.string() + ": malformed image");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path.string() + ": " + e.what());
  }
  write_file_atomically(path, bytes);
}

void render_png(const std::filesystem::path& path, const MeshTopology& topology, const Frame& frame,
                const std::vector<glm::vec3>& front_srgb, const std::vector<glm::vec3>& back_srgb,
                const Camera& camera, int width, int height) {
  write_png(path, render_image(topology, frame, front_srgb, back_srgb, camera, width, height));
}

std::vector<Image> turntable_images(const MeshTopology& topology, const Frame& frame,
                                    const std::vector<glm::vec3>& front_srgb,
                                    const std::vector<glm::vec3>& back_srgb, const Camera& camera, int count,
                                    int width, int height) {
  validate_mesh(topology, frame, "render_turntable");
  if (count < 1) throw std::invalid_argument("render_turntable: count must be >= 1");
  validate_colours(topology.num_vertices, front_srgb, back_srgb);
  EmbreeSceneParams scene_params;
  scene_params.mode = EmbreeSceneParams::BuildMode::Rebuild;
  scene_params.robust = false;
  const EmbreeScene scene(topology, frame, scene_params);
  std::vector<Image> images;
  for (int i = 0; i < count; ++i)
    images.push_back(
        render_image(scene, frame, front_srgb, back_srgb, orbit(camera, 360.0 * i / count), width, height));
  return images;
}

std::vector<std::filesystem::path> render_turntable(const std::filesystem::path& directory,
                                                    const std::string& stem, const MeshTopology& topology,
                                                    const Frame& frame,
                                                    const std::vector<glm::vec3>& front_srgb,
                                                    const std::vector<glm::vec3>& back_srgb,
                                                    const Camera& camera, int count, int width, int height) {
  const std::vector<Image> images =
      turntable_images(topology, frame, front_srgb, back_srgb, camera, count, width, height);
  std::vector<std::filesystem::path> written;
  for (int i = 0; i < count; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "_%03d.png", i);
    written.push_back(directory / (stem + name));
    write_png(written.back(), images[std::size_t(i)]);
  }
  return written;
}

// ---------------------------------------------------------------------------------------------- labels,
// panels

int text_width(std::string_view text, int scale) {
  return text.empty() ? 0 : (static_cast<int>(text.size()) * kGlyphAdvance - 1) * scale;
}

void draw_text(Image& image, int x, int y, std::string_view text, glm::u8vec3 colour, int scale) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const Glyph& g = glyph(text[i]);
    const int gx = x + static_cast<int>(i) * kGlyphAdvance * scale;
    for (int row = 0; row < 7; ++row)
      for (int col = 0; col < 5; ++col) {
        if (((g.rows[row] >> (4 - col)) & 1) == 0) continue;
        for (int dy = 0; dy < scale; ++dy)
          for (int dx = 0; dx < scale; ++dx) {
            const int px = gx + col * scale + dx, py = y + row * scale + dy;
            if (px >= 0 && py >= 0 && px < image.width && py < image.height) image.set_pixel(px, py, colour);
          }
      }
  }
}

glm::vec3 viridis(double t) {
  static const std::array<glm::vec3, 9> stops = {
      glm::vec3(68, 1, 84),    glm::vec3(71, 44, 122),  glm::vec3(59, 81, 139),
      glm::vec3(44, 113, 142), glm::vec3(33, 144, 141), glm::vec3(39, 173, 129),
      glm::vec3(92, 200, 99),  glm::vec3(170, 220, 50), glm::vec3(253, 231, 37)};
  const double x = std::clamp(t, 0.0, 1.0) * (stops.size() - 1);
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(x), stops.size() - 2);
  const float f = static_cast<float>(x - double(i));
  return glm::mix(stops[i], stops[i + 1], f) / 255.0f;
}

namespace {
std::string legend_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}
}  // namespace

Image with_legend(const Image& image, double lo, double hi, std::string_view title) {
  constexpr int kScale = 2, kPad = 8, kBar = 14, kText = 7 * kScale;
  const int height = image.height + kPad + kBar + 4 + kText + kPad + kText + kPad;
  Image out(image.width, height, {40, 40, 40});
  std::copy(image.rgb.begin(), image.rgb.end(), out.rgb.begin());
  const int x0 = kPad, x1 = image.width - kPad;
  const int y0 = image.height + kPad;
  for (int x = x0; x < x1; ++x) {
    const glm::vec3 c = viridis(double(x - x0) / std::max(1, x1 - x0 - 1));
    const glm::u8vec3 rgb(static_cast<std::uint8_t>(std::lround(255 * c.x)),
                          static_cast<std::uint8_t>(std::lround(255 * c.y)),
                          static_cast<std::uint8_t>(std::lround(255 * c.z)));
    for (int y = y0; y < y0 + kBar; ++y) out.set_pixel(x, y, rgb);
  }
  const int ty = y0 + kBar + 4;
  const glm::u8vec3 ink(235, 235, 235);
  const std::string low = legend_number(lo), mid = legend_number((lo + hi) / 2), high = legend_number(hi);
  draw_text(out, x0, ty, low, ink, kScale);
  draw_text(out, (x0 + x1 - text_width(mid, kScale)) / 2, ty, mid, ink, kScale);
  draw_text(out, x1 - text_width(high, kScale), ty, high, ink, kScale);
  draw_text(out, std::max(kPad, (image.width - text_width(title, kScale)) / 2), ty + kText + kPad, title, ink,
            kScale);
  return out;
}

Image side_by_side(std::span<const LabeledImage> panels) {
  constexpr int kScale = 2, kPad = 6, kGap = 4;
  const int bar = 7 * kScale + 2 * kPad;
  int width = 0, height = 0;
  for (const LabeledImage& p : panels) {
    if (p.image == nullptr) throw std::invalid_argument("side_by_side: null image");
    width += p.image->width;
    height = std::max(height, p.image->height);
  }
  if (!panels.empty()) width += kGap * static_cast<int>(panels.size() - 1);
  Image out(std::max(width, 1), height + bar, {40, 40, 40});
  int x0 = 0;
  for (const LabeledImage& p : panels) {
    const Image& img = *p.image;
    for (int y = 0; y < img.height; ++y)
      std::copy_n(img.rgb.begin() + static_cast<std::ptrdiff_t>(y) * img.width * 3, img.width * 3,
                  out.rgb.begin() + (static_cast<std::ptrdiff_t>(y + bar) * out.width + x0) * 3);
    const int tx = x0 + std::max(kPad, (img.width - text_width(p.label, kScale)) / 2);
    draw_text(out, tx, kPad, p.label, {235, 235, 235}, kScale);
    x0 += img.width + kGap;
  }
  return out;
}

}  // namespace pleat
