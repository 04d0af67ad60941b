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

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "kinetic/engine.hpp"
#include "shading/cone_cache.hpp"
#include "sim_io/job_spec.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_report.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/scene.hpp"
#include "sim_io/sequence_plan.hpp"
#include "support/input_error.hpp"
#include "support/nearest_name.hpp"

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
  if (!f64 && !f32) {
    // Other floats (big-endian ones, float16, longdouble) are converted to native float64.
    if (dtype.kind() != 'f')
      bad(what + ": dtype " + dtype_name(view.array) + "; expected float64 or float32");
    view.array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(view.array);
  }
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
  if (array.attr("dtype").attr("isnative").cast<bool>() == false)  // big-endian: in native byte order
    array = array.attr("astype")(array.dtype().attr("newbyteorder")("="));
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

/// The keyword options of Engine and sky_visibility, those of `pleat visibility`: None unless given.
struct EngineOptions {
  py::object engine = py::none(), orientations = py::none(), spacing = py::none(), spacing_edges = py::none(),
             planes = py::none(), adaptive = py::none(), max_missing = py::none(), cone_storage = py::none(),
             cone_reconstruction = py::none(), paper = py::none(), plan = py::none(), occluders = py::none(),
             ground = py::none(), threads = py::none(), max_edit_fraction = py::none(),
             contact_tolerance = py::none();
};

struct EngineOption {
  const char* name;
  py::object EngineOptions::*field;
};
const EngineOption kEngineOptions[] = {
    {"engine", &EngineOptions::engine},
    {"orientations", &EngineOptions::orientations},
    {"spacing", &EngineOptions::spacing},
    {"spacing_edges", &EngineOptions::spacing_edges},
    {"planes", &EngineOptions::planes},
    {"adaptive", &EngineOptions::adaptive},
    {"max_missing", &EngineOptions::max_missing},
    {"cone_storage", &EngineOptions::cone_storage},
    {"cone_reconstruction", &EngineOptions::cone_reconstruction},
    {"paper", &EngineOptions::paper},
    {"plan", &EngineOptions::plan},
    {"occluders", &EngineOptions::occluders},
    {"ground", &EngineOptions::ground},
    {"threads", &EngineOptions::threads},
    {"max_edit_fraction", &EngineOptions::max_edit_fraction},
    {"contact_tolerance", &EngineOptions::contact_tolerance},
};

/// Reads keyword options; `also`: the caller's own keywords, taken out of `kwargs` before. A name of neither
/// raises TypeError "unknown option 'spcing'; did you mean 'spacing'?" (the nearest name, if near).
EngineOptions engine_options(const py::kwargs& kwargs, const std::vector<std::string>& also = {}) {
  EngineOptions options;
  std::vector<std::string> names(also);
  for (const EngineOption& o : kEngineOptions) names.push_back(o.name);
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key);
    const auto* found = std::find_if(std::begin(kEngineOptions), std::end(kEngineOptions),
                                     [&](const EngineOption& o) { return name == o.name; });
    if (found == std::end(kEngineOptions)) {
      const std::string near = nearest_name(name, names);
      std::string message = "unknown option '" + name + "'";
      if (!near.empty()) {
        message += "; did you mean '" + near + "'?";
      } else {
        message += " (options:";
        for (const std::string& n : names) message += " " + n;
        message += ")";
      }
      throw py::type_error(message);
    }
    options.*(found->field) = py::reinterpret_borrow<py::object>(value);
  }
  return options;
}

/// The job specification of the keywords (sim_io/job_spec.hpp), the command line's: TypeError naming a
/// keyword of the wrong type, and its one check (ValueError naming the keyword) on the values.
JobSpec job_spec_of(const EngineOptions& o) {
  JobSpec spec;
  PlanOptions& plan = spec.plan;
  plan.orientations = option(o.orientations, plan.orientations, "orientations", "an int");
  if (!o.spacing.is_none()) plan.spacing = option(o.spacing, 0.0, "spacing", "a number");
  if (!o.spacing_edges.is_none())
    plan.spacing_edges = option(o.spacing_edges, 0.0, "spacing_edges", "a number");
  if (!o.planes.is_none()) plan.planes_per_orientation = option(o.planes, 0, "planes", "an int");
  plan.adaptive = option(o.adaptive, false, "adaptive", "a bool");
  plan.max_missing = option(o.max_missing, plan.max_missing, "max_missing", "a number");
  plan.storage = option(o.cone_storage, plan.storage, "cone_storage", "a str");
  plan.reconstruction = option(o.cone_reconstruction, plan.reconstruction, "cone_reconstruction", "a str");
  plan.paper = option(o.paper, false, "paper", "a bool");
  if (!o.plan.is_none())  // str or PathLike
    plan.plan_file = py::module_::import("os").attr("fspath")(o.plan).cast<std::string>();
  spec.engine = option(o.engine, spec.engine, "engine", "a str");
  spec.max_edit_fraction =
      option(o.max_edit_fraction, spec.max_edit_fraction, "max_edit_fraction", "a number");
  spec.threads = option(o.threads, 0, "threads", "an int");
  if (!o.ground.is_none()) spec.ground = option(o.ground, std::string(), "ground", "a str like 'y=0'");
  if (!o.contact_tolerance.is_none())
    spec.contact_tolerance = option(o.contact_tolerance, 0.0, "contact_tolerance", "a number");
  spec.check(JobSpec::Naming::Keywords);
  return spec;
}

/// Ctrl+C while pleat computes without the GIL. Python runs signal handlers on its main thread only, when
/// asked: poll() (EngineParams::poll, called on every TBB thread during a frame) does so on the thread that
/// called pleat, at most every 20 ms, with the GIL. A handler's exception (KeyboardInterrupt) is kept and
/// the frame abandoned (Interrupted thrown through the engine); rethrow() raises it in Python.
class InterruptCheck {
 public:
  struct Interrupted {};

  /// Before a computation, with or without the GIL: the calling thread is the one polled.
  void begin() {
    m_caller = std::this_thread::get_id();
    m_last = std::chrono::steady_clock::now();
  }
  void poll() {
    if (std::this_thread::get_id() != m_caller) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - m_last < std::chrono::milliseconds(20)) return;
    m_last = now;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  }

 private:
  std::thread::id m_caller;
  std::chrono::steady_clock::time_point m_last;
};

/// Adds `note` to the Python exception being raised (PEP 678, Python 3.11+; left out before) and raises it.
[[noreturn]] void raise_with_note(py::error_already_set& error, const std::string& note) {
  const py::object value = error.value();
  if (py::hasattr(value, "add_note")) value.attr("add_note")(note);
  throw error;
}

/// The Python Engine: the cloth (faces, its frames), its scene and plan, and a pleat::Engine over them.
class PyEngine {
 public:
  PyEngine(py::object faces, py::object positions, const EngineOptions& options) {
    const JobSpec spec = job_spec_of(options);
    EngineParams params;
    params.kind = engine_kind_from_name(spec.engine);
    params.policy.max_edit_fraction = spec.max_edit_fraction;
    params.poll = [this] { m_interrupt.poll(); };  // the engine is made in place and never moves
    const PlanOptions& plan_options = spec.plan;
    std::vector<GroundPlane> grounds;
    if (!spec.ground.empty()) grounds.push_back(parse_ground_plane(spec.ground));
    const std::optional<double> tolerance = spec.contact_tolerance;
    const int thread_count = spec.threads;
    m_arena =
        std::make_unique<tbb::task_arena>(thread_count > 0 ? thread_count : int(tbb::task_arena::automatic));

    // Every array is checked with the GIL held; the work below runs without it.
    m_meshes.push_back(mesh_arrays(faces, positions, ""));
    add_occluders(options.occluders);
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
    m_without_surface.assign(m_cloth->topology().num_vertices, 0);
    for (Index w : isolated_vertices(m_cloth->topology())) m_without_surface[w] = 1;
  }
  PyEngine(const PyEngine&) = delete;
  PyEngine& operator=(const PyEngine&) = delete;

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
    m_interrupt.begin();
    try {
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
    } catch (py::error_already_set& e) {
      raise_with_note(e, "pleat: interrupted during the frame (the Engine stays usable)");
    }
    result.cones = std::move(cones);
    return result;
  }

  /// Sky visibility of the given frames (indices among those given to the constructor) into `out` (float64,
  /// C-contiguous, (len(frames), V, 2)), computed as `pleat visibility --frames` does. Between frames, with
  /// the GIL: `progress` (None, an object with update(n) such as a tqdm bar, or a callable (done, total)),
  /// then Python's signal handlers; within a frame, InterruptCheck. An exception (KeyboardInterrupt, the
  /// callback's) leaves the finished frames in `out` and says how many in a note. Frames with cloth sunk
  /// deeper than the contact tolerance give one UserWarning.
  void sky_visibility_of(const std::vector<std::size_t>& frames, const py::object& progress, double* out) {
    const std::size_t vertices = m_cloth->num_input_vertices();
    const bool updates = !progress.is_none() && py::hasattr(progress, "update");
    std::size_t finished = 0;  // frames whose rows of `out` are written
    std::size_t sunk_frames = 0, first_sunk = 0, first_count = 0;
    try {
      for (std::size_t k = 0; k < frames.size(); ++k) {
        m_interrupt.begin();
        {
          py::gil_scoped_release release;
          m_arena->execute([&] {
            const FrameVisibility& vis = m_engine->compute(m_scene->frame(frames[k]));
            if (vis.stats.penetrating_vertices > 0 && sunk_frames++ == 0) {
              first_sunk = frames[k];
              first_count = vis.stats.penetrating_vertices;
            }
            const std::vector<Index>& welded = *m_welded_of_input;
            double* row = out + k * vertices * 2;
            const double nan = std::numeric_limits<double>::quiet_NaN();
            for (std::size_t v = 0; v < welded.size(); ++v) {
              const bool surface = !m_without_surface[welded[v]];  // else no visibility: NaN
              row[2 * v] = surface ? vis.measure(Side::Front, welded[v]).sky_visibility : nan;
              row[2 * v + 1] = surface ? vis.measure(Side::Back, welded[v]).sky_visibility : nan;
            }
          });
        }
        finished = k + 1;
        if (updates)
          progress.attr("update")(1);
        else if (!progress.is_none())
          progress(finished, frames.size());
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      }
    } catch (py::error_already_set& e) {
      raise_with_note(e, "pleat: stopped after " + std::to_string(finished) + " of " +
                             std::to_string(frames.size()) +
                             " frames (their values are in out[:" + std::to_string(finished) + "])");
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
  }

  std::size_t num_vertices() const { return m_cloth->num_input_vertices(); }
  bool given_one_frame() const { return m_meshes[0].positions.data.one_frame; }
  std::size_t num_frames() const { return m_cloth->num_frames(); }
  /// The planes of the first frame given (a lattice plan's planes follow each frame's cloth).
  std::size_t num_planes() const {
    std::vector<SlicingPlane> planes;
    planes_for_frame(m_engine->plan(), cloth_vertices(m_cloth->topology()), m_cloth->frame(0), planes);
    return planes.size();
  }
  std::string kind() const { return engine_kind_name(m_engine->kind()); }

 private:
  /// The occluders option: (faces, positions) pairs or pleat.load results, checked with the GIL.
  void add_occluders(const py::object& occluders) {
    if (occluders.is_none()) return;
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
  }

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
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t v = 0; v < welded.size(); ++v)
      for (int s = 0; s < 2; ++s) {
        const ConeMeasures& m = vis.measure(Side(s), welded[v]);
        const bool surface = !m_without_surface[welded[v]];  // else no visibility: NaN
        sky[2 * v + s] = surface ? m.sky_visibility : nan;
        solid[2 * v + s] = surface ? m.solid_angle : nan;
        for (int c = 0; c < 3; ++c) bent[(2 * v + s) * 3 + c] = surface ? m.bent_normal[c] : nan;
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
      if (std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) > kMaxCoordinate)
        throw InputError("positions", "vertex " + std::to_string(v),
                         "a coordinate beyond +-2^53, where doubles stop holding every integer (an exploded "
                         "simulation, or a transform far from the origin?)");
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
  InterruptCheck m_interrupt;
  std::vector<char> m_without_surface;  ///< per welded vertex: no triangle uses it
};

/// The frame indices `frames` selects among `count`: None (all), an int, a slice, a str "A:B" or "N" as
/// `pleat visibility --frames` reads it, or a sequence of ints; negatives count from the end.
std::vector<std::size_t> frame_selection(const py::object& frames, std::size_t count) {
  const py::object all = py::module_::import("builtins").attr("range")(count);
  py::object chosen;
  if (frames.is_none()) {
    chosen = all;
  } else if (py::isinstance<py::str>(frames)) {  // "A:B", "A:", ":B", "N"
    const std::string text = frames.cast<std::string>();
    const std::size_t colon = text.find(':');
    const auto bound = [&](const std::string& part) -> py::object {
      if (part.empty()) return py::none();
      try {
        std::size_t used = 0;
        const long long value = std::stoll(part, &used);
        if (used == part.size()) return py::int_(value);
      } catch (const std::exception&) {
      }
      throw py::value_error("frames: '" + text + "' is not A:B, A:, :B or N");
    };
    if (colon == std::string::npos) {
      py::list one;
      one.append(all[bound(text)]);
      chosen = one;
    } else {
      chosen = all[py::slice(bound(text.substr(0, colon)), bound(text.substr(colon + 1)), py::none())];
    }
  } else if (py::isinstance<py::slice>(frames)) {
    chosen = all[frames];
  } else if (py::isinstance<py::int_>(frames) || py::hasattr(frames, "__index__")) {
    py::list one;
    one.append(all[frames]);
    chosen = one;
  } else {
    py::list many;
    for (py::handle f : frames) many.append(all[f]);
    chosen = many;
  }
  std::vector<std::size_t> indices;
  for (py::handle f : chosen) indices.push_back(f.cast<std::size_t>());
  if (indices.empty()) throw py::value_error("frames: selects no frame of " + std::to_string(count));
  return indices;
}

/// pleat.read_cone_cache's fields: A (T, I, 2) per input vertex, the input frame indices (T,), the times
/// (T,).
py::tuple read_cone_cache(const std::string& path) {
  std::optional<ConeCacheReader> reader;
  {
    py::gil_scoped_release release;
    reader.emplace(path);
  }
  const ConeCacheHeader& header = reader->header();
  const py::ssize_t frames = py::ssize_t(header.frames.size()),
                    inputs = py::ssize_t(header.welded_of_input.size());
  py::array_t<double> sky({frames, inputs, py::ssize_t(2)});
  py::array_t<std::int64_t> indices(frames);
  py::array_t<double> times(frames);
  double* a = sky.mutable_data();
  std::int64_t* f = indices.mutable_data();
  double* t = times.mutable_data();
  {
    py::gil_scoped_release release;
    FrameVisibility frame;
    for (py::ssize_t k = 0; k < frames; ++k) {
      reader->read_frame_unchecked(std::size_t(k), frame);
      for (py::ssize_t v = 0; v < inputs; ++v)
        for (int side = 0; side < 2; ++side)
          a[(k * inputs + v) * 2 + side] =
              frame.measures[side][header.welded_of_input[std::size_t(v)]].sky_visibility;
      f[k] = header.frames[std::size_t(k)];
      t[k] = header.times[std::size_t(k)];
    }
  }
  return py::make_tuple(sky, indices, times);
}

/// pleat.sky_visibility: the engine's options, and frames=, progress=, out= (python/pleat/__init__.py).
py::array_t<double> sky_visibility(py::object faces, py::object positions, py::kwargs kwargs) {
  const auto take = [&](const char* name) {
    if (!kwargs.contains(name)) return py::object(py::none());
    return kwargs.attr("pop")(name).cast<py::object>();
  };
  const py::object frames = take("frames"), progress = take("progress"), out_given = take("out");
  auto engine =
      std::make_unique<PyEngine>(faces, positions, engine_options(kwargs, {"frames", "progress", "out"}));
  const std::vector<std::size_t> chosen = frame_selection(frames, engine->num_frames());
  const py::ssize_t n = py::ssize_t(chosen.size()), v = py::ssize_t(engine->num_vertices());
  const bool one = engine->given_one_frame() && frames.is_none();
  const std::vector<py::ssize_t> shape =
      one ? std::vector<py::ssize_t>{v, 2} : std::vector<py::ssize_t>{n, v, 2};
  py::array_t<double> out;
  if (out_given.is_none()) {
    out = py::array_t<double>(shape);
  } else {
    const py::array given = py::reinterpret_borrow<py::array>(out_given);
    if (!py::isinstance<py::array>(out_given) || !given.dtype().is(py::dtype::of<double>()) ||
        !(given.flags() & py::array::c_style) || !given.writeable() ||
        std::vector<py::ssize_t>(given.shape(), given.shape() + given.ndim()) != shape)
      bad("out: expected a writable C-contiguous float64 array of shape (" + std::to_string(one ? v : n) +
          (one ? "" : ", " + std::to_string(v)) + ", 2)");
    out = py::reinterpret_borrow<py::array_t<double>>(out_given);
  }
  engine->sky_visibility_of(chosen, progress, out.mutable_data());
  return out;
}

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
       adaptive=False, max_missing=0.05, cone_storage="aimed-on-fan", cone_reconstruction="grouped", paper=False,
       plan=None,
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
      .def(py::init([](py::object faces, py::object positions, py::kwargs options) {
             return std::make_unique<PyEngine>(faces, positions, engine_options(options));
           }),
           py::arg("faces"), py::arg("positions"))
      .def("compute", &PyEngine::compute, py::arg("positions"), py::kw_only(), py::arg("frame_index") = 0,
           py::arg("keep_cones") = true,
           "compute(positions, *, frame_index=0, keep_cones=True) -> FrameResult: the frame whose (V, 3) "
           "positions are given; frame_index (< the frames given to Engine) picks the animated occluders' "
           "positions. keep_cones=False leaves out the cones (FrameResult.cone), which cost memory.")
      .def_property_readonly("num_vertices", &PyEngine::num_vertices)
      .def_property_readonly("num_frames", &PyEngine::num_frames)
      .def_property_readonly("num_planes", &PyEngine::num_planes)
      .def_property_readonly("engine", &PyEngine::kind);

  m.def("_load", &load, py::arg("path"), py::arg("cache") = py::none());
  m.def("_sky_visibility", &sky_visibility, py::arg("faces"), py::arg("positions"));
  m.def("_read_cone_cache", &read_cone_cache, py::arg("path"));
}
