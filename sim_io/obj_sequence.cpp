#include "sim_io/obj_sequence.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <functional>
#include <map>
#include <optional>

#include "sim_io/input_formats.hpp"
#include "sim_io/obj_format.hpp"
#include "support/input_error.hpp"

namespace pleat {

namespace {

// A filename pattern with one integer conversion: prefix, then the number (zero-padded or space-padded to
// `width`), then suffix.
struct FramePattern {
  std::string prefix;
  std::string suffix;
  int width = 0;
  bool zero_pad = false;

  std::string format(long long n) const {
    std::string digits = std::to_string(n);
    if (int(digits.size()) < width)
      digits.insert(0, std::size_t(width) - digits.size(), zero_pad ? '0' : ' ');
    return prefix + digits + suffix;
  }
};

// Replaces "%%" by "%" in a literal part; returns nullopt if a lone '%' remains.
std::optional<std::string> unescape(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '%') {
      out += s[i];
    } else if (i + 1 < s.size() && s[i + 1] == '%') {
      out += '%';
      ++i;
    } else {
      return std::nullopt;
    }
  }
  return out;
}

std::optional<FramePattern> parse_pattern(const std::string& s) {
  std::optional<FramePattern> found;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '%') continue;
    if (i + 1 < s.size() && s[i + 1] == '%') {
      ++i;
      continue;
    }
    if (found) return std::nullopt;  // a second conversion
    std::size_t j = i + 1;
    FramePattern p;
    if (j < s.size() && s[j] == '0') {
      p.zero_pad = true;
      ++j;
    }
    while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j])))
      p.width = p.width * 10 + (s[j++] - '0');
    if (j >= s.size() || (s[j] != 'd' && s[j] != 'i') || p.width > 32) return std::nullopt;
    auto prefix = unescape(s.substr(0, i));
    auto suffix = unescape(s.substr(j + 1));
    if (!prefix || !suffix) return std::nullopt;
    p.prefix = *prefix;
    p.suffix = *suffix;
    found = p;
    i = j;
  }
  return found;
}

// Natural order: runs of digits compare as numbers, everything else byte by byte.
bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const bool da = std::isdigit(static_cast<unsigned char>(a[i])),
               db = std::isdigit(static_cast<unsigned char>(b[j]));
    if (da && db) {
      std::size_t ie = i, je = j;
      while (ie < a.size() && std::isdigit(static_cast<unsigned char>(a[ie]))) ++ie;
      while (je < b.size() && std::isdigit(static_cast<unsigned char>(b[je]))) ++je;
      std::string_view na(a.data() + i, ie - i), nb(b.data() + j, je - j);
      while (na.size() > 1 && na.front() == '0') na.remove_prefix(1);
      while (nb.size() > 1 && nb.front() == '0') nb.remove_prefix(1);
      if (na.size() != nb.size()) return na.size() < nb.size();
      if (na != nb) return na < nb;
      i = ie;
      j = je;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

// The last run of digits in each file's name without extension (frame_0012.obj: 12), when every name has
// one and they increase strictly; otherwise the files' indices.
std::vector<std::int64_t> numbers_in_names(const std::vector<std::filesystem::path>& files) {
  std::vector<std::int64_t> numbers;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::string stem = files[i].stem().string();
    const auto last = stem.find_last_of("0123456789");
    std::int64_t n = 0;
    bool found = false;
    if (last != std::string::npos) {
      const auto first = stem.find_last_not_of("0123456789", last);
      const std::size_t begin = first == std::string::npos ? 0 : first + 1;
      const auto [stop, error] = std::from_chars(stem.data() + begin, stem.data() + last + 1, n);
      found = error == std::errc() && stop == stem.data() + last + 1;
    }
    if (!found || (!numbers.empty() && n <= numbers.back())) {
      numbers.resize(files.size());
      for (std::size_t k = 0; k < files.size(); ++k) numbers[k] = std::int64_t(k);
      return numbers;
    }
    numbers.push_back(n);
  }
  return numbers;
}

// A file name split around the last run of digits of its stem: f_0012.obj is ("f_", "0012", ".obj").
struct NumberedName {
  std::string prefix, digits, suffix;
  long long number = 0;
};

std::optional<NumberedName> split_number(const std::string& filename) {
  const std::string stem = std::filesystem::path(filename).stem().string();
  const auto last = stem.find_last_of("0123456789");
  if (last == std::string::npos) return std::nullopt;
  const auto before = stem.find_last_not_of("0123456789", last);
  const std::size_t begin = before == std::string::npos ? 0 : before + 1;
  NumberedName name{filename.substr(0, begin), stem.substr(begin, last + 1 - begin),
                    filename.substr(last + 1)};
  const auto [stop, error] =
      std::from_chars(name.digits.data(), name.digits.data() + name.digits.size(), name.number);
  if (error != std::errc()) return std::nullopt;
  return name;
}

// Refuses a numbering that is not regular: the numbers (increasing) must advance by one step throughout, 1
// (every frame) or the first two files' difference (every Nth frame exported). Throws InputError naming the
// first missing file (`name_of` a number) and the sequence (`what`).
void check_regular_numbering(const std::vector<long long>& numbers,
                             const std::function<std::string(long long)>& name_of, const std::string& what) {
  if (numbers.size() < 2) return;
  const long long step = numbers[1] - numbers[0];
  for (std::size_t i = 1; i < numbers.size(); ++i) {
    if (numbers[i] - numbers[i - 1] == step) continue;
    const bool later = numbers[i] - numbers[i - 1] > step;
    throw InputError(later ? name_of(numbers[i - 1] + step) : what, "",
                     std::string(later ? "missing frame" : "irregular numbering") +
                         " in the numbered sequence " + what + " (found " + std::to_string(numbers[0]) +
                         " to " + std::to_string(numbers[i - 1]) +
                         (step == 1 ? "" : " every " + std::to_string(step)) + ", then " +
                         std::to_string(numbers[i]) + ")");
  }
}

// Frames after the first are parsed for their positions and polygons only: their polygons must be the first
// frame's, and they are split into triangles as the first frame's are.
class ObjSequenceSource : public FrameSource {
 public:
  ObjSequenceSource(std::vector<std::filesystem::path> files, const ObjMesh& first, double scene_fps)
      : m_files(std::move(files)),
        m_numbers(numbers_in_names(m_files)),
        m_polygon_corners(first.polygon_corners),
        m_polygon_starts(first.polygon_starts),
        m_num_vertices(first.positions.size()),
        m_scene_fps(scene_fps) {}

  std::size_t num_frames() const override { return m_files.size(); }
  std::int64_t source_frame(std::size_t i) const override { return m_numbers.at(i); }
  double frame_time(std::size_t i) const override { return double(m_numbers.at(i)) / m_scene_fps; }
  std::vector<glm::dvec3> read_frame(std::size_t i) const override {
    ObjMesh mesh = read_obj_polygons(m_files.at(i));
    const std::string file = m_files[i].string();
    const std::string first = m_files.front().string();
    if (mesh.positions.size() != m_num_vertices)
      throw InputError(file, "frame " + std::to_string(i),
                       "vertex-count mismatch: " + std::to_string(mesh.positions.size()) +
                           " vertices, the first frame (" + first + ") has " +
                           std::to_string(m_num_vertices));
    if (mesh.num_polygons + 1 != m_polygon_starts.size())
      throw InputError(file, "frame " + std::to_string(i),
                       "connectivity differs from the first frame (" + first +
                           "): " + std::to_string(mesh.num_polygons) + " faces instead of " +
                           std::to_string(m_polygon_starts.size() - 1));
    for (std::size_t p = 0; p < mesh.num_polygons; ++p)
      if (mesh.polygon_starts[p + 1] != m_polygon_starts[p + 1] ||
          !std::equal(mesh.polygon_corners.begin() + std::ptrdiff_t(mesh.polygon_starts[p]),
                      mesh.polygon_corners.begin() + std::ptrdiff_t(mesh.polygon_starts[p + 1]),
                      m_polygon_corners.begin() + std::ptrdiff_t(m_polygon_starts[p])))
        throw InputError(
            file, "frame " + std::to_string(i),
            "connectivity differs from the first frame (" + first + ") at face " + std::to_string(p));
    return std::move(mesh.positions);
  }

 private:
  std::vector<std::filesystem::path> m_files;
  std::vector<std::int64_t> m_numbers;
  std::vector<Index> m_polygon_corners;
  std::vector<std::size_t> m_polygon_starts;
  std::size_t m_num_vertices;
  double m_scene_fps;
};

}  // namespace

bool is_frame_pattern(const std::string& input) { return parse_pattern(input).has_value(); }

std::vector<std::filesystem::path> expand_frame_pattern(const std::string& pattern) {
  const std::filesystem::path as_path(pattern);
  const std::string filename = as_path.filename().string();
  const auto parsed = parse_pattern(filename);
  if (!parsed || as_path.parent_path().string().find('%') != std::string::npos)
    throw InputError(pattern, "",
                     "a frame pattern needs exactly one %d (or %0Nd) conversion, in the file name");
  const std::filesystem::path dir =
      as_path.has_parent_path() ? as_path.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw InputError(pattern, "", "no such directory: " + dir.string());
  std::map<long long, std::filesystem::path> numbered;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= parsed->prefix.size() + parsed->suffix.size()) continue;
    if (name.compare(0, parsed->prefix.size(), parsed->prefix) != 0) continue;
    if (name.compare(name.size() - parsed->suffix.size(), parsed->suffix.size(), parsed->suffix) != 0)
      continue;
    std::string middle =
        name.substr(parsed->prefix.size(), name.size() - parsed->prefix.size() - parsed->suffix.size());
    const auto first_digit = middle.find_first_not_of(' ');
    if (first_digit == std::string::npos) continue;
    long long n = 0;
    const char* begin = middle.data() + first_digit;
    const char* end = middle.data() + middle.size();
    const auto [stop, error] = std::from_chars(begin, end, n);
    if (error != std::errc() || stop != end || n < 0) continue;
    if (parsed->format(n) != name) continue;  // e.g. f_12.obj does not match f_%04d.obj
    numbered.emplace(n, entry.path());
  }
  if (ec) throw InputError(pattern, "", "cannot list " + dir.string() + ": " + ec.message());
  if (numbered.empty()) throw InputError(pattern, "", "no file matches the pattern");
  std::vector<std::filesystem::path> files;
  std::vector<long long> numbers;
  for (const auto& [n, path] : numbered) numbers.push_back(n), files.push_back(path);
  check_regular_numbering(
      numbers, [&](long long n) { return (dir / parsed->format(n)).string(); }, pattern);
  return files;
}

namespace {

// Refuses a directory whose .obj files (two or more, in natural order) are not one numbered sequence: each
// name the same text around its last run of digits, the numbers distinct and regular
// (check_regular_numbering).
void check_one_sequence(const std::filesystem::path& directory, const std::vector<std::string>& names) {
  if (names.size() < 2) return;
  const auto not_one = [&](const std::string& why) {
    return InputError(directory.string(), "",
                      "its .obj files are not one numbered sequence: " + why +
                          " (give each sequence its own directory, or name one by a pattern like "
                          "frames/f_%04d.obj)");
  };
  std::vector<NumberedName> split;
  for (const std::string& name : names) {
    std::optional<NumberedName> numbered = split_number(name);
    if (!numbered) throw not_one(name + " has no frame number in its name");
    if (!split.empty() &&
        (numbered->prefix != split.front().prefix || numbered->suffix != split.front().suffix))
      throw not_one(names.front() + " and " + name + " differ in more than their frame numbers");
    if (!split.empty() && numbered->number == split.back().number)
      throw not_one(names[split.size() - 1] + " and " + name + " both number frame " +
                    std::to_string(numbered->number));
    split.push_back(std::move(*numbered));
  }
  std::vector<long long> numbers;
  for (const NumberedName& n : split) numbers.push_back(n.number);
  const NumberedName& first = split.front();
  const bool padded = first.digits.size() > 1 && first.digits.front() == '0';
  check_regular_numbering(
      numbers,
      [&](long long n) {
        std::string digits = std::to_string(n);
        if (padded && digits.size() < first.digits.size())
          digits.insert(0, first.digits.size() - digits.size(), '0');
        return (directory / (first.prefix + digits + first.suffix)).string();
      },
      directory.string());
}

}  // namespace

std::vector<std::filesystem::path> list_obj_directory(const std::filesystem::path& directory) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(directory, ec)) {
    std::string extension = entry.path().extension().string();
    for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (extension == ".obj" && !entry.is_directory()) names.push_back(entry.path().filename().string());
  }
  if (ec) throw InputError(directory.string(), "", "cannot list the directory: " + ec.message());
  if (names.empty()) throw InputError(directory.string(), "", "no .obj files in the directory");
  std::sort(names.begin(), names.end(), natural_less);
  check_one_sequence(directory, names);
  std::vector<std::filesystem::path> files;
  files.reserve(names.size());
  for (const auto& n : names) files.push_back(directory / n);
  return files;
}

MeshSequence load_obj_sequence(const std::string& name, const std::vector<std::filesystem::path>& files,
                               double scene_fps, const LoadScan& scan) {
  if (files.empty()) throw InputError(name, "", "no frames");
  ObjMesh first = read_obj(files.front());
  const auto num_vertices = Index(first.positions.size());
  SurfaceAttributes surface = surface_of(first);
  auto source = std::make_unique<ObjSequenceSource>(files, first, scene_fps);
  std::vector<Triangle> triangles = std::move(first.triangles);
  return MeshSequence(name, std::move(triangles), num_vertices, std::move(source), scan, std::move(surface));
}

void write_obj_sequence(const std::string& pattern, const MeshSequence& sequence, int first_number) {
  const std::filesystem::path as_path(pattern);
  const auto parsed = parse_pattern(as_path.filename().string());
  if (!parsed) throw std::invalid_argument("write_obj_sequence: the pattern needs exactly one %d conversion");
  for (std::size_t i = 0; i < sequence.num_frames(); ++i)
    write_obj(as_path.parent_path() / parsed->format(first_number + (long long)i), sequence.topology(),
              sequence.frame(i).positions);
}

namespace {

bool is_obj_sequence(const std::filesystem::path& input) {
  std::error_code ec;
  return std::filesystem::is_directory(input, ec) || is_frame_pattern(input.string());
}

MeshSequence open_obj_sequence(const std::filesystem::path& input, const std::filesystem::path&,
                               const LoadOptions& options) {
  const std::string name = input.string();
  std::error_code ec;
  const auto files =
      std::filesystem::is_directory(input, ec) ? list_obj_directory(input) : expand_frame_pattern(name);
  return load_obj_sequence(name, files, options.scene_fps, options.scan);
}

std::vector<std::filesystem::path> obj_sequence_files(const std::filesystem::path& input) {
  std::vector<std::filesystem::path> files;
  try {
    std::error_code ec;
    files = std::filesystem::is_directory(input, ec) ? list_obj_directory(input)
                                                     : expand_frame_pattern(input.string());
  } catch (const std::exception&) {
    files.clear();
  }
  if (files.empty()) files.push_back(input);
  return files;
}

}  // namespace

namespace formats {
extern const MeshFormat kObjSequence{"",
                                     "a directory of .obj files or a printf pattern like frames/f_%04d.obj",
                                     "an OBJ sequence",
                                     is_obj_sequence,
                                     open_obj_sequence,
                                     obj_sequence_files};
}  // namespace formats

}  // namespace pleat
