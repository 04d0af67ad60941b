#include "sim_io/job_spec.hpp"

#include <cmath>
#include <stdexcept>

namespace pleat {

void JobSpec::check(Naming naming) const {
  plan.check(naming);
  const bool cli = naming == Naming::CommandLine;
  if (!(max_edit_fraction >= 0))
    throw std::invalid_argument(std::string(cli ? "--max-edit-fraction" : "max_edit_fraction") +
                                ": must be >= 0");
  if (threads < 0)
    throw std::invalid_argument(std::string(cli ? "--threads" : "threads") +
                                ": must be >= 0 (0 or None: all cores)");
  if (contact_tolerance && !(std::isfinite(*contact_tolerance) && *contact_tolerance >= 0))
    throw std::invalid_argument(std::string(cli ? "--contact-tolerance" : "contact_tolerance") +
                                ": must be a finite distance >= 0");
}

}  // namespace pleat
