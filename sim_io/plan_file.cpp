#include "sim_io/plan_file.hpp"

#include <fstream>
#include <sstream>

#include "static_core/plan_codec.hpp"
#include "support/atomic_file.hpp"
#include "support/input_error.hpp"

namespace pleat {

void write_plan_file(const std::filesystem::path& path, const SlicingPlan& plan) {
  write_file_atomically(path, plan_to_json(plan));
}

SlicingPlan read_plan_file(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name, "", "cannot open the plan file");
  std::stringstream text;
  text << in.rdbuf();
  return plan_from_json(text.str(), name);
}

}  // namespace pleat
