// The job specification (sim_io/job_spec.hpp) has one check, which the command line (cli/job.hpp) and the
// Python module both run: the same message for the same bad value, naming the option as each spells it, and
// on the command line as the option is parsed, before any file is read.
#include "sim_io/job_spec.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <limits>
#include <string>

#include "test_support.hpp"

namespace pleat {
namespace {

std::string message_of(const JobSpec& spec, JobSpec::Naming naming) {
  try {
    spec.check(naming);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

struct BadValue {
  std::function<void(JobSpec&)> set;
  std::string option;   ///< the command line's spelling, as given
  std::string keyword;  ///< the Python module's
  std::string message;  ///< after the name
};

const BadValue kBadValues[] = {
    {[](JobSpec& s) { s.plan.spacing_edges = -1.0; }, "--spacing-edges -1", "spacing_edges",
     ": must be a finite number > 0, got -1"},
    {[](JobSpec& s) { s.plan.storage = "nearest"; }, "--cone-storage nearest", "cone_storage",
     ": 'nearest' is not "},
    {[](JobSpec& s) { s.plan.reconstruction = "best"; }, "--cone-reconstruction best", "cone_reconstruction",
     ": 'best' is not grouped or nearest-circle"},
    {[](JobSpec& s) { s.max_edit_fraction = -0.5; }, "--max-edit-fraction -0.5", "max_edit_fraction",
     ": must be >= 0"},
    {[](JobSpec& s) { s.contact_tolerance = -1.0; }, "--contact-tolerance -1", "contact_tolerance",
     ": must be a finite distance >= 0"},
};

TEST(JobSpec, OneCheckOneMessagePerBadValueInEitherSpelling) {
  EXPECT_EQ(message_of(JobSpec{}, JobSpec::Naming::Keywords), "");
  for (const BadValue& bad : kBadValues) {
    JobSpec spec;
    bad.set(spec);
    const std::string option = bad.option.substr(0, bad.option.find(' '));
    EXPECT_EQ(message_of(spec, JobSpec::Naming::Keywords).rfind(bad.keyword + bad.message, 0), 0u)
        << message_of(spec, JobSpec::Naming::Keywords);
    EXPECT_EQ(message_of(spec, JobSpec::Naming::CommandLine).rfind(option + bad.message, 0), 0u)
        << message_of(spec, JobSpec::Naming::CommandLine);
  }
  JobSpec threads;
  threads.threads = -1;
  EXPECT_EQ(message_of(threads, JobSpec::Naming::Keywords), "threads: must be >= 0 (0 or None: all cores)");
  JobSpec nan;
  nan.contact_tolerance = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message_of(nan, JobSpec::Naming::Keywords), "");
}

TEST(JobSpec, TheCommandLineSaysTheSameBeforeReadingAnyFile) {
  // The input does not exist: the bad value is what is reported, with the usage exit code.
  test::TempDir dir;
  for (const BadValue& bad : kBadValues)
    for (const std::string command : {"visibility", "shade"}) {
      if (command == "shade" && bad.option.rfind("--max-edit-fraction", 0) == 0) continue;  // kinetic only
      const std::string out = (dir / (command == "shade" ? "o.glb" : "o.csv")).string();
      const auto result =
          test::run_pleat(command + " " + (dir / "missing.obj").string() + " -o " + out + " " + bad.option);
      const std::string option = bad.option.substr(0, bad.option.find(' '));
      EXPECT_EQ(result.exit_code, 2) << command << " " << bad.option << ": " << result.output;
      EXPECT_NE(result.output.find(option + bad.message), std::string::npos)
          << command << " " << bad.option << ": " << result.output;
      EXPECT_EQ(result.output.find("missing.obj"), std::string::npos) << result.output;
      EXPECT_FALSE(std::filesystem::exists(out));
    }
}

}  // namespace
}  // namespace pleat
