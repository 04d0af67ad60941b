// The kept state of a KineticVisibility, for tests: what each plane carries between frames.
#pragma once

#include <cstddef>

namespace pleat {
class KineticVisibility;  // kinetic/kinetic_visibility.hpp, which names this struct its friend
}  // namespace pleat

namespace pleat::kinetic {

class KineticSlice;

struct KineticInspect {
  /// The kept state of plane `plane` of the plan (throws std::out_of_range past the last plane).
  static const KineticSlice& slice(const KineticVisibility& visibility, std::size_t plane);
};

}  // namespace pleat::kinetic
