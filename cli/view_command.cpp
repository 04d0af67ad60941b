// `pleat view`: a self-contained page that plays a glb written by `pleat shade` and relights it live from the
// cones the glb carries (_SKY_VISIBILITY, _BENT_CONE; sim_io/gltf_writer.hpp).
//
// DIR gets index.html and viewer.js (cli/viewer/, compiled in), three.js r111 with its GLTFLoader and
// OrbitControls copied from Debian's libjs-three (PLEAT_THREE_JS_DIR), and scene.js holding the glb in
// base64, so the page works from file:// (browsers refuse to fetch local files from a page) with no network.
// Every file is staged in DIR first (support/atomic_file.hpp's StagedFiles) and moved in when all are
// complete.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "cli/cli_options.hpp"
#include "cli/commands.hpp"
#include "cli/global_options.hpp"
#include "cli/job_error.hpp"
#include "support/atomic_file.hpp"
#include "support/byte_order.hpp"
#include "support/input_error.hpp"

namespace pleat::cli {

extern const char* const kViewerHtml;
extern const char* const kViewerJs;

namespace {

namespace fs = std::filesystem;

struct ViewOptions {
  std::string input;
  std::string output;
};

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open the file");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Throws InputError unless `glb` is a binary glTF whose first primitive carries pleat's cone attributes.
void check_glb(const std::string& file, const std::string& glb) {
  const auto* p = reinterpret_cast<const unsigned char*>(glb.data());
  if (glb.size() < 20 || bytes::load_u32_le(p) != 0x46546C67u)
    throw InputError(file, "byte 0", "not a binary glTF (.glb)");
  const std::uint32_t json_bytes = bytes::load_u32_le(p + 12);
  if (bytes::load_u32_le(p + 16) != 0x4E4F534Au || json_bytes > glb.size() - 20)
    throw InputError(file, "byte 12", "the glb's JSON chunk is missing or truncated");
  const nlohmann::json document = nlohmann::json::parse(glb.substr(20, json_bytes), nullptr, false);
  if (document.is_discarded()) throw InputError(file, "byte 20", "the glb's JSON does not parse");
  const nlohmann::json* attributes = nullptr;
  if (document.contains("meshes") && document["meshes"].is_array() && !document["meshes"].empty()) {
    const nlohmann::json& mesh = document["meshes"][0];
    if (mesh.contains("primitives") && mesh["primitives"].is_array() && !mesh["primitives"].empty())
      attributes =
          mesh["primitives"][0].contains("attributes") ? &mesh["primitives"][0]["attributes"] : nullptr;
  }
  if (attributes && attributes->contains("_SKY_VISIBILITY_FRONT"))
    throw InputError(file, "mesh 0",
                     "is the input layout (`pleat shade --glb-layout input`); `pleat view` plays the default "
                     "layout: write it with --glb-layout sides");
  if (!attributes || !attributes->contains("_SKY_VISIBILITY") || !attributes->contains("_BENT_CONE"))
    throw InputError(
        file, "mesh 0",
        "carries no visibility cones (_SKY_VISIBILITY, _BENT_CONE): write it with `pleat shade`");
}

std::string base64(const std::string& data) {
  static const char* const alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((data.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < data.size(); i += 3) {
    const unsigned v =
        (unsigned char)data[i] << 16 | (unsigned char)data[i + 1] << 8 | (unsigned char)data[i + 2];
    for (int k = 3; k >= 0; --k) out.push_back(alphabet[(v >> (6 * k)) & 63]);
  }
  if (i < data.size()) {
    const bool two = i + 1 < data.size();
    const unsigned v = (unsigned char)data[i] << 16 | (two ? (unsigned char)data[i + 1] << 8 : 0u);
    out.push_back(alphabet[(v >> 18) & 63]);
    out.push_back(alphabet[(v >> 12) & 63]);
    out.push_back(two ? alphabet[(v >> 6) & 63] : '=');
    out.push_back('=');
  }
  return out;
}

void run_view(const ViewOptions& options) {
  check_outputs(
      {},
      {{"-o",
        options.output,
        {"index.html", "viewer.js", "scene.js", "three.min.js", "GLTFLoader.js", "OrbitControls.js"}}},
      {{"INPUT", options.input}});
  const std::string glb = read_bytes(options.input);
  check_glb(options.input, glb);
  const fs::path three = PLEAT_THREE_JS_DIR;
  const std::pair<const char*, const char*> library[] = {
      {"build/three.min.js", "three.min.js"},
      {"examples/js/loaders/GLTFLoader.js", "GLTFLoader.js"},
      {"examples/js/controls/OrbitControls.js", "OrbitControls.js"}};
  for (const auto& [from, to] : library)
    if (!fs::is_regular_file(three / from))
      throw std::runtime_error("three.js not found: " + (three / from).string() +
                               " is missing (Debian package libjs-three; scripts/setup.sh installs it)");

  // Every file staged in DIR (a listed temporary: a signal removes it), then all moved in together.
  const fs::path dir = fs::absolute(options.output);
  StagedFiles page(dir);
  page.add("index.html", kViewerHtml);
  page.add("viewer.js", kViewerJs);
  for (const auto& [from, to] : library) page.add(to, read_bytes(three / from));
  page.add("scene.js", "// " + fs::path(options.input).filename().string() +
                           ", written by pleat view\nwindow.PLEAT_GLB = \"" + base64(glb) + "\";\n");
  {
    const CommitWindow window;
    page.commit();
  }
  report() << "wrote " << (dir / "index.html").string()
           << ": open it in a browser (file:// works), or serve it: python3 -m http.server -d "
           << dir.string() << "\n";
}

}  // namespace

void register_view_command(CLI::App& app) {
  auto options = std::make_shared<ViewOptions>();
  CLI::App* cmd =
      app.add_subcommand("view",
                         "Write a self-contained web page that plays a glb written by `pleat shade` and "
                         "relights it live from the "
                         "visibility cones it carries (sky, a sun you move, albedo; or the baked colours).");
  cmd->add_option("input", options->input, "a .glb written by pleat shade")->required();
  cmd->add_option("-o,--output", options->output, "directory for the page (index.html and its scripts)")
      ->required();
  cmd->footer(
      "Example:\n  pleat shade curtain.obj --cache curtain.pc2 -o curtain.glb --light sky:1\n"
      "  pleat view curtain.glb -o curtain_view && chromium curtain_view/index.html");
  cmd->callback([options] { on_rank_zero_alone([&] { run_view(*options); }); });
}

}  // namespace pleat::cli
