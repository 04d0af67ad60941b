// pleat._pleat, the compiled part of the Python module pleat (python/pleat/__init__.py documents the API):
// numpy arrays in and out, read where they lie when they are C-contiguous float64 or float32, the GIL
// released while computing, TBB threads in an arena of the caller's size.
//
// The cloth is made into a MeshSequence exactly as the command line makes it from a file (the same welding
// of coinciding vertices, the same faces removed, the same bounds), its occluders into a Scene, and the plan
// by PlanOptions (sim_io/sequence_plan.hpp), so that the same frames and options give the same bits as
// `pleat visibility`. Results are in the caller's vertex order.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/task_arena.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "kinetic/engine.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/scene.hpp"
#include "sim_io/sequence_plan.hpp"
#include "static_core/input_error.hpp"

namespace py = pybind11;

namespace pleat::python {
namespace {

// What MeshSequence takes as the time of frame i where the caller gives none: the rate of formats without
// times. Times do not enter visibility.
double frame_time_of(std::size_t i) { return double(i) / kDefaultSceneFps; }

/// Positions given by the caller, (T, V, 3) or (V, 3), where they lie: float64 or float32, C-contiguous.
/// Plain data, read without the GIL while the array it points into is kept alive by its owner (MeshArrays).
struct PositionsData {
  const void* data = nullptr;
  bool single_precision = false;
  bool one_frame = false;  ///< given as (V, 3)
  std::size_t frames = 0, vertices = 0;

  glm::dvec3 at(std::size_t frame, std::size_t vertex) const {
    const std::size_t i = (frame * vertices + vertex) * 3;
    if (single_precision) {
      const float* p = static_cast<const float*>(data) + i;
      return {p[0], p[1], p[2]};
    }
    const double* p = static_cast<const double*>(data) + i;
    return {p[0], p[1], p[2]};
  }
};

/// The caller's positions array (or, if not C-contiguous, a C-contiguous float64 copy of it) and its data.
struct PositionsView {
  py::array array;
  PositionsData data;
};

[[noreturn]] void bad(const std::string& message) { throw py::value_error(message); }

std::string shape_text(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) text += (d ? ", " : "") + std::to_string(a.shape(d));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

std::string dtype_name(const py::array& array) { return py::str(py::handle(array.dtype())); }

py::array as_array(py::handle object, const std::string& what) {
  if (object.is_none()) bad(what + ": None is not an array");
  py::array array = py::array::ensure(object);
  if (!array) {
    PyErr_Clear();
    bad(what + ": not convertible to a numpy array");
  }
  return array;
}

/// `allowed_ndim`: 2 for one frame (V, 3), 3 for frames (T, V, 3), 0 for either.
PositionsView positions_view(py::handle object, const std::string& what, int allowed_ndim = 0) {
  PositionsView view;
  view.array = as_array(object, what);
  const py::dtype dtype = view.array.dtype();
  const bool f64 = dtype.is(py::dtype::of<double>()), f32 = dtype.is(py::dtype::of<float>());
  if (!f64 && !f32) bad(what + ": dtype " + dtype_name(view.array) + "; expected float64 or float32");
  const py::ssize_t ndim = view.array.ndim();
  const bool ndim_ok = allowed_ndim ? ndim == allowed_ndim : (ndim == 2 || ndim == 3);
  if (!ndim_ok || view.array.shape(ndim - 1) != 3)
    bad(what + ": shape " + shape_text(view.array) + "; expected " +
        (allowed_ndim == 2   ? "(V, 3)"
         : allowed_ndim == 3 ? "(T, V, 3)"
                             : "(T, V, 3) or (V, 3)"));
  if (!(view.array.flags() & py::array::c_style))
    view.array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(view.array);
  PositionsData& data = view.data;
  data.single_precision = view.array.dtype().is(py::dtype::of<float>());
  data.one_frame = ndim == 2;
  data.frames = data.one_frame ? 1 : std::size_t(view.array.shape(0));
  data.vertices = std::size_t(view.array.shape(ndim - 2));
  if (data.frames == 0) bad(what + ": no frames (shape " + shape_text(view.array) + ")");
  if (data.vertices == 0) bad(what + ": no vertices (shape " + shape_text(view.array) + ")");
  if (data.vertices > std::size_t(UINT32_MAX)) bad(what + ": more vertices than pleat indexes (2^32 - 1)");
  data.data = view.array.data();
  return view;
}

template <typename T>
void read_faces(const py::array& array, std::size_t num_vertices, const std::string& what,
                std::vector<Triangle>& faces) {
  const T* p = static_cast<const T*>(array.data());
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int c = 0; c < 3; ++c) {
      const T v = p[f * 3 + c];
      if (v < 0 || std::uint64_t(v) >= num_vertices)
        bad(what + ": face " + std::to_string(f) + ": vertex index " + std::to_string(v) + " out of range (" +
            std::to_string(num_vertices) + " vertices)");
      faces[f][c] = Index(v);
    }
}

/// Faces (F, 3) of any integer dtype, checked against `num_vertices`.
std::vector<Triangle> faces_of(py::handle object, std::size_t num_vertices, const std::string& what) {
  py::array array = as_array(object, what);
  const char kind = array.dtype().kind();
  if (kind != 'i' && kind != 'u')
    bad(what + ": dtype " + dtype_name(array) + "; expected integers (int32 or int64)");
  if (array.ndim() != 2 || array.shape(1) != 3)
    bad(what + ": shape " + shape_text(array) + "; expected (F, 3) (triangles)");
  if (array.shape(0) == 0) bad(what + ": no faces");
  array = py::array::ensure(array, py::array::c_style);
  std::vector<Triangle> faces(std::size_t(array.shape(0)));
  switch (array.itemsize() * (kind == 'i' ? 1 : -1)) {
    case 1:
      read_faces<std::int8_t>(array, num_vertices, what, faces);
      break;
    case 2:
      read_faces<std::int16_t>(array, num_vertices, what, faces);
      break;
    case 4:
      read_faces<std::int32_t>(array, num_vertices, what, faces);
      break;
    case 8:
      read_faces<std::int64_t>(array, num_vertices, what, faces);
      break;
    case -1:
      read_faces<std::uint8_t>(array, num_vertices, what, faces);
      break;
    case -2:
      read_faces<std::uint16_t>(array, num_vertices, what, faces);
      break;
    case -4:
      read_faces<std::uint32_t>(array, num_vertices, what, faces);
      break;
    case -8:
      read_faces<std::uint64_t>(array, num_vertices, what, faces);
      break;
    default:
      bad(what + ": unsupported integer dtype " + dtype_name(array));
  }
  return faces;
}

/// The caller's frames, read in place (the owner of the view keeps its array alive).
class ArrayFrames : public FrameSource {
 public:
  explicit ArrayFrames(const PositionsData& view) : m_view(view) {}
  std::size_t num_frames() const override { return m_view.frames; }
  double frame_time(std::size_t i) const override { return frame_time_of(i); }
  std::vector<glm::dvec3> read_frame(std::size_t i) const override {
    std::vector<glm::dvec3> positions(m_view.vertices);
    for (std::size_t v = 0; v < m_view.vertices; ++v) positions[v] = m_view.at(i, v);
    return positions;
  }

 private:
  PositionsData m_view;
};

/// A mesh given as arrays: its faces and its view (made with the GIL held).
struct MeshArrays {
  std::string name;
  std::vector<Triangle> faces;
  PositionsView positions;
};

/// `prefix`: "" for the cloth, "occluders[k] " for an occluder (errors name the array).
MeshArrays mesh_arrays(py::handle faces, py::handle positions, const std::string& prefix) {
  MeshArrays mesh;
  mesh.name = prefix.empty() ? "positions" : prefix.substr(0, prefix.size() - 1);
  mesh.positions = positions_view(positions, prefix + "positions");
  mesh.faces = faces_of(faces, mesh.positions.data.vertices, prefix + "faces");
  return mesh;
}

/// The sequence the command line would make of the same triangles and frames (welded, validated). Runs
/// without the GIL; `mesh` must outlive the sequence (its array holds the frames).
MeshSequence make_sequence(const MeshArrays& mesh) {
  const PositionsData& data = mesh.positions.data;
  return MeshSequence(mesh.name, mesh.faces, Index(data.vertices), std::make_unique<ArrayFrames>(data));
}

using Cones = std::array<std::vector<VisibilityCone>, 2>;

/// One frame's results, in the caller's vertex order.
struct FrameResult {
  py::array_t<double> sky_visibility;  ///< (V, 2): front, back
  py::array_t<double> bent_normals;    ///< (V, 2, 3)
  py::array_t<double> solid_angles;    ///< (V, 2)
  std::shared_ptr<const Cones> cones;  ///< per welded vertex; null when not kept
  std::shared_ptr<const std::vector<Index>> welded_of_input;
  std::size_t penetrating_vertices = 0;  ///< deeper than the contact tolerance in an occluder or the ground

  py::list cone(py::ssize_t vertex, py::handle side) const {
    if (!cones) throw py::value_error("cone: this result was computed with keep_cones=False");
    if (vertex < 0 || std::size_t(vertex) >= welded_of_input->size())
      throw py::index_error("cone: vertex " + std::to_string(vertex) + " out of range (" +
                            std::to_string(welded_of_input->size()) + " vertices)");
    int s = -1;
    if (py::isinstance<py::str>(side)) {
      const std::string name = side.cast<std::string>();
      s = name == "front" ? 0 : name == "back" ? 1 : -1;
    } else if (py::isinstance<py::int_>(side)) {
      s = side.cast<int>();
    }
    if (s != 0 && s != 1) throw py::value_error("cone: side must be 0 or 'front', 1 or 'back'");
    py::list pieces;
    for (const SphericalPolygon& piece : (*cones)[s][(*welded_of_input)[std::size_t(vertex)]].pieces) {
      py::array_t<double> directions({py::ssize_t(piece.size()), py::ssize_t(3)});
      double* out = directions.mutable_data();
      for (std::size_t k = 0; k < piece.size(); ++k)
        for (int c = 0; c < 3; ++c) out[k * 3 + c] = piece[k][c];
      pieces.append(std::move(directions));
    }
    return pieces;
  }
};

/// An option's value, `fallback` for None; TypeError naming the option for a value of another type.
template <typename T>
T option(const py::object& value, T fallback, const char* name, const char* expected) {
  if (value.is_none()) return fallback;
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw py::type_error(std::string(name) + ": expected " + expected + ", got " +
                         std::string(py::str(py::type::handle_of(value).attr("__name__"))));
  }
}

/// Where one frame's results go: the data of a FrameResult's arrays.
struct Outputs {
  double* sky;
  double* bent;
  double* solid;
};

/// The Python Engine: the cloth (faces, its frames), its scene and plan, and a pleat::Engine over them.
class PyEngine {
 public:
  PyEngine(py::object faces, py::object positions, const std::string& engine, py::object orientations,
           py::object spacing, py::object spacing_edges, py::object planes, bool adaptive, double max_missing,
           const std::string& cone_storage, bool paper, py::object plan, py::object occluders,
           py::object ground, py::object threads, double max_edit_fraction, py::object contact_tolerance) {
    EngineParams params;
    params.kind = engine_kind_from_name(engine);
    if (!(max_edit_fraction >= 0)) bad("max_edit_fraction: must be >= 0");
    params.policy.max_edit_fraction = max_edit_fraction;
    PlanOptions plan_options;
    plan_options.orientations = option(orientations, plan_options.orientations, "orientations", "an int");
    plan_options.spacing = option(spacing, 0.0, "spacing", "a number");
    plan_options.spacing_edges = option(spacing_edges, 0.0, "spacing_edges", "a number");
    if (!spacing_edges.is_none() && !(plan_options.spacing_edges > 0)) bad("spacing_edges: must be > 0");
    plan_options.planes_per_orientation = option(planes, 0, "planes", "an int");
    plan_options.adaptive = adaptive;
    plan_options.max_missing = max_missing;
    plan_options.storage = cone_storage;
    plan_options.paper = paper;
    if (!plan.is_none()) plan_options.plan_file = py::str(plan).cast<std::string>();  // str or PathLike
    plan_options.check();
    std::vector<GroundPlane> grounds;
    if (!ground.is_none())
      grounds.push_back(parse_ground_plane(option(ground, std::string(), "ground", "a str like 'y=0'")));
    std::optional<double> tolerance;
    if (!contact_tolerance.is_none()) {
      tolerance = option(contact_tolerance, 0.0, "contact_tolerance", "a number");
      if (!(std::isfinite(*tolerance) && *tolerance >= 0))
        bad("contact_tolerance: must be a finite distance >= 0");
    }
    const int thread_count = option(threads, 0, "threads", "an int");
    if (thread_count < 0) bad("threads: must be >= 0 (0 or None: all cores)");
    m_arena =
        std::make_unique<tbb::task_arena>(thread_count > 0 ? thread_count : int(tbb::task_arena::automatic));

    // Every array is checked with the GIL held; the work below runs without it.
    m_meshes.push_back(mesh_arrays(faces, positions, ""));
    std::size_t k = 0;
    for (py::handle occluder : occluders) {
      const std::string name = "occluders[" + std::to_string(k++) + "]";
      if (py::hasattr(occluder, "faces") && py::hasattr(occluder, "positions")) {
        m_meshes.push_back(mesh_arrays(occluder.attr("faces"), occluder.attr("positions"), name + " "));
      } else {
        if (!py::isinstance<py::sequence>(occluder) || py::isinstance<py::str>(occluder) ||
            py::len(occluder) != 2)
          bad(name + ": expected a (faces, positions) pair or a pleat.load result");
        const py::sequence pair = py::reinterpret_borrow<py::sequence>(occluder);
        m_meshes.push_back(mesh_arrays(pair[0], pair[1], name + " "));
      }
    }
    py::gil_scoped_release release;
    m_arena->execute([&] {
      m_cloth = std::make_unique<MeshSequence>(make_sequence(m_meshes[0]));
      std::vector<Scene::LoadedOccluder> loaded;
      for (std::size_t i = 1; i < m_meshes.size(); ++i)
        loaded.push_back({m_meshes[i].name, make_sequence(m_meshes[i])});
      m_scene = std::make_unique<Scene>(Scene::with_loaded(*m_cloth, std::move(loaded), grounds, tolerance));
      m_engine = std::make_unique<Engine>(m_scene->topology(), plan_options.make(*m_cloth), params);
    });
    m_welded_of_input = std::make_shared<const std::vector<Index>>(m_cloth->welded_of_input());
  }

  /// The results of one frame of the cloth given as (V, 3) positions; `frame_index` picks the occluders'
  /// positions (animated ones) among the frames given to the constructor.
  FrameResult compute(py::object positions, py::ssize_t frame_index, bool keep_cones) {
    const PositionsView given = positions_view(positions, "positions", 2);
    const PositionsData& view = given.data;
    const std::size_t vertices = m_cloth->num_input_vertices();
    if (view.vertices != vertices)
      bad("positions: " + std::to_string(view.vertices) + " vertices; the engine's cloth has " +
          std::to_string(vertices));
    if (frame_index < 0 || std::size_t(frame_index) >= m_cloth->num_frames())
      throw py::index_error("frame_index " + std::to_string(frame_index) + " out of range (" +
                            std::to_string(m_cloth->num_frames()) + " frames given to Engine)");
    FrameResult result = allocate_result();
    const Outputs out{result.sky_visibility.mutable_data(), result.bent_normals.mutable_data(),
                      result.solid_angles.mutable_data()};  // with the GIL
    std::shared_ptr<Cones> cones;
    {
      py::gil_scoped_release release;
      m_arena->execute([&] {
        Frame frame;
        frame.time = m_cloth->frame_time(std::size_t(frame_index));
        frame.positions = welded_positions(view);
        const FrameVisibility& vis =
            m_engine->compute(m_scene->with_occluders(std::size_t(frame_index), frame));
        write_result(vis, out);
        result.penetrating_vertices = vis.stats.penetrating_vertices;
        if (keep_cones) cones = std::make_shared<Cones>(vis.cones);
      });
    }
    result.cones = std::move(cones);
    return result;
  }

  /// Sky visibility (T, V, 2) of every frame given to the constructor ((V, 2) if given as (V, 3)), computed
  /// as `pleat visibility` does.
  py::array_t<double> sky_visibility_of_frames() {
    const PositionsData& given = m_meshes[0].positions.data;
    const py::ssize_t frames = py::ssize_t(m_cloth->num_frames()), vertices = m_cloth->num_input_vertices();
    py::array_t<double> out = given.one_frame ? py::array_t<double>({vertices, py::ssize_t(2)})
                                              : py::array_t<double>({frames, vertices, py::ssize_t(2)});
    double* data = out.mutable_data();
    std::size_t sunk_frames = 0, first_sunk = 0, first_count = 0;
    {
      py::gil_scoped_release release;
      m_arena->execute([&] {
        for (std::size_t f = 0; f < std::size_t(frames); ++f) {
          const FrameVisibility& vis = m_engine->compute(m_scene->frame(f));
          if (vis.stats.penetrating_vertices > 0 && sunk_frames++ == 0) {
            first_sunk = f;
            first_count = vis.stats.penetrating_vertices;
          }
          const std::vector<Index>& welded = *m_welded_of_input;
          double* row = data + f * std::size_t(vertices) * 2;
          for (std::size_t v = 0; v < welded.size(); ++v) {
            row[2 * v] = vis.measure(Side::Front, welded[v]).sky_visibility;
            row[2 * v + 1] = vis.measure(Side::Back, welded[v]).sky_visibility;
          }
        }
      });
    }
    if (sunk_frames > 0) {
      const std::string message =
          "cloth lies deeper than the contact tolerance (" +
          std::to_string(m_scene->topology().contact_tolerance) +
          ") inside an occluder or below the ground in " + std::to_string(sunk_frames) +
          " frames (first: frame " + std::to_string(first_sunk) + ", " + std::to_string(first_count) +
          " vertices); those vertices were taken as lying on the surface (contact_tolerance=)";
      if (PyErr_WarnEx(PyExc_UserWarning, message.c_str(), 1) != 0) throw py::error_already_set();
    }
    return out;
  }

  std::size_t num_vertices() const { return m_cloth->num_input_vertices(); }
  std::size_t num_frames() const { return m_cloth->num_frames(); }
  /// The planes of the first frame given (a lattice plan's planes follow each frame's cloth).
  std::size_t num_planes() const {
    std::vector<SlicingPlane> planes;
    planes_for_frame(m_engine->plan(), cloth_vertices(m_cloth->topology()), m_cloth->frame(0), planes);
    return planes.size();
  }
  std::string kind() const { return engine_kind_name(m_engine->kind()); }

 private:
  FrameResult allocate_result() const {
    const py::ssize_t v = py::ssize_t(m_cloth->num_input_vertices());
    FrameResult result;
    result.sky_visibility = py::array_t<double>({v, py::ssize_t(2)});
    result.bent_normals = py::array_t<double>({v, py::ssize_t(2), py::ssize_t(3)});
    result.solid_angles = py::array_t<double>({v, py::ssize_t(2)});
    result.welded_of_input = m_welded_of_input;
    return result;
  }

  // Writes through the data pointers of a FrameResult's arrays (taken with the GIL).
  void write_result(const FrameVisibility& vis, const Outputs& out) const {
    double* sky = out.sky;
    double* bent = out.bent;
    double* solid = out.solid;
    const std::vector<Index>& welded = *m_welded_of_input;
    for (std::size_t v = 0; v < welded.size(); ++v)
      for (int s = 0; s < 2; ++s) {
        const ConeMeasures& m = vis.measure(Side(s), welded[v]);
        sky[2 * v + s] = m.sky_visibility;
        solid[2 * v + s] = m.solid_angle;
        for (int c = 0; c < 3; ++c) bent[(2 * v + s) * 3 + c] = m.bent_normal[c];
      }
  }

  /// The caller's positions on the welded vertices. Vertices welded by the constructor (they coincided in
  /// every frame it was given) must coincide here too.
  std::vector<glm::dvec3> welded_positions(const PositionsData& view) const {
    const std::vector<Index>& welded = *m_welded_of_input;
    const Index num_welded = m_cloth->topology().num_vertices;
    std::vector<glm::dvec3> positions(num_welded);
    std::vector<Index> first(num_welded, Index(-1));
    for (std::size_t v = 0; v < welded.size(); ++v) {
      const glm::dvec3 p = view.at(0, v);
      if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
        throw InputError("positions", "vertex " + std::to_string(v), "non-finite coordinate");
      const Index w = welded[v];
      if (first[w] == Index(-1)) {
        first[w] = Index(v);
        positions[w] = p;
      } else if (positions[w] != p) {
        throw InputError("positions", "vertex " + std::to_string(v),
                         "coincides with vertex " + std::to_string(first[w]) +
                             " in every frame given to Engine (so they were welded) but not here; give "
                             "Engine this frame too");
      }
    }
    return positions;
  }

  // Declaration order is destruction order reversed: the arrays outlive everything that reads them.
  std::vector<MeshArrays> m_meshes;  ///< the cloth, then each occluder
  std::unique_ptr<tbb::task_arena> m_arena;
  std::unique_ptr<MeshSequence> m_cloth;
  std::unique_ptr<Scene> m_scene;
  std::unique_ptr<Engine> m_engine;
  std::shared_ptr<const std::vector<Index>> m_welded_of_input;
};

/// pleat.load's fields: faces (F, 3) int64, positions (T, V, 3) float64, fps, source frames.
py::tuple load(const std::string& path, const std::optional<std::string>& cache) {
  std::optional<MeshSequence> sequence;
  {
    py::gil_scoped_release release;
    sequence.emplace(load_sequence(path, cache.value_or("")));
  }
  const std::vector<Triangle>& triangles = sequence->input_triangles();
  const py::ssize_t frames = py::ssize_t(sequence->num_frames()), vertices = sequence->num_input_vertices();
  py::array_t<std::int64_t> faces({py::ssize_t(triangles.size()), py::ssize_t(3)});
  py::array_t<double> positions({frames, vertices, py::ssize_t(3)});
  py::array_t<std::int64_t> source_frames(frames);
  std::int64_t* f = faces.mutable_data();
  double* p = positions.mutable_data();
  std::int64_t* s = source_frames.mutable_data();
  {
    py::gil_scoped_release release;
    for (std::size_t t = 0; t < triangles.size(); ++t)
      for (int c = 0; c < 3; ++c) f[t * 3 + c] = triangles[t][c];
    for (py::ssize_t i = 0; i < frames; ++i) {
      const std::vector<glm::dvec3> frame = sequence->input_positions(std::size_t(i));
      for (std::size_t v = 0; v < frame.size(); ++v)
        for (int c = 0; c < 3; ++c) p[(std::size_t(i) * frame.size() + v) * 3 + c] = frame[v][c];
      s[i] = sequence->source_frame(std::size_t(i));
    }
  }
  return py::make_tuple(faces, positions, sequence->frame_rate(), source_frames);
}

}  // namespace
}  // namespace pleat::python

PYBIND11_MODULE(_pleat, m) {
  using namespace pleat::python;
  m.doc() = "pleat's compiled core; use the package pleat (python/pleat/__init__.py).";
  m.attr("__version__") = PLEAT_VERSION;
  static py::exception<pleat::InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const pleat::InputError& e) {
      input_error(e.what());
    }
  });

  py::class_<FrameResult>(m, "FrameResult", "One frame's results, in the caller's vertex order.")
      .def_readonly("sky_visibility", &FrameResult::sky_visibility, "(V, 2) float64: A of the front, back")
      .def_readonly("bent_normals", &FrameResult::bent_normals, "(V, 2, 3) float64: unit bent normals")
      .def_readonly("solid_angles", &FrameResult::solid_angles, "(V, 2) float64: steradians of each cone")
      .def_readonly("penetrating_vertices", &FrameResult::penetrating_vertices,
                    "cloth vertices deeper than the contact tolerance inside an occluder or below the ground "
                    "(taken as lying on its surface)")
      .def("cone", &FrameResult::cone, py::arg("vertex"), py::arg("side"),
           "The cone of `vertex` on `side` (0 or 'front', 1 or 'back'): a list of its pieces, each an (n, 3) "
           "array of unit edge directions, counter-clockwise about the side's normal.");

  py::class_<PyEngine>(m, "Engine",
                       R"(The cones of a cloth, frame by frame, over fixed faces and a fixed plan.

Engine(faces, positions, *, engine="kinetic", orientations=None, spacing=None, spacing_edges=None, planes=None,
       adaptive=False, max_missing=0.05, cone_storage="aimed-on-fan", paper=False, plan=None,
       occluders=(), ground=None, threads=None, max_edit_fraction=0.5, contact_tolerance=None)

faces: (F, 3) integers; positions: (T, V, 3) or (V, 3) float64/float32, every frame the engine will be asked
for: the plan is made from them as `pleat visibility` makes it (orientations and spacing from the first frame,
planes over the box of all), and vertices that coincide in all of them are welded. The options are those of
`pleat visibility` (None: its default); occluders: a sequence of (faces, positions) pairs, positions (V, 3)
static or (T, V, 3) animated, or of pleat.load results; ground: "y=0" (a floor; "-y=0": solid above);
contact_tolerance: how far behind an open occluder cloth still rests on it, and the depth beyond which sunk
vertices are reported (None: half the mean edge length); threads: None or 0 for all cores.
C-contiguous float64/float32 positions are read in place, not copied: leave them unchanged while the engine
lives (animated occluders are read from them frame by frame).)")
      .def(py::init<py::object, py::object, const std::string&, py::object, py::object, py::object,
                    py::object, bool, double, const std::string&, bool, py::object, py::object, py::object,
                    py::object, double, py::object>(),
           py::arg("faces"), py::arg("positions"), py::kw_only(), py::arg("engine") = "kinetic",
           py::arg("orientations") = py::none(), py::arg("spacing") = py::none(),
           py::arg("spacing_edges") = py::none(), py::arg("planes") = py::none(), py::arg("adaptive") = false,
           py::arg("max_missing") = 0.05, py::arg("cone_storage") = "aimed-on-fan", py::arg("paper") = false,
           py::arg("plan") = py::none(), py::arg("occluders") = py::tuple(), py::arg("ground") = py::none(),
           py::arg("threads") = py::none(), py::arg("max_edit_fraction") = 0.5,
           py::arg("contact_tolerance") = py::none())
      .def("compute", &PyEngine::compute, py::arg("positions"), py::kw_only(), py::arg("frame_index") = 0,
           py::arg("keep_cones") = true,
           "compute(positions, *, frame_index=0, keep_cones=True) -> FrameResult: the frame whose (V, 3) "
           "positions are given; frame_index (< the frames given to Engine) picks the animated occluders' "
           "positions. keep_cones=False leaves out the cones (FrameResult.cone), which cost memory.")
      .def("_sky_visibility_of_frames", &PyEngine::sky_visibility_of_frames)
      .def_property_readonly("num_vertices", &PyEngine::num_vertices)
      .def_property_readonly("num_frames", &PyEngine::num_frames)
      .def_property_readonly("num_planes", &PyEngine::num_planes)
      .def_property_readonly("engine", &PyEngine::kind);

  m.def("_load", &load, py::arg("path"), py::arg("cache") = py::none());
}
