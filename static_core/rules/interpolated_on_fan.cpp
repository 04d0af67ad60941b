// The interpolated-on-fan storage rule (docs/method.md §7): as nearest-on-fan, but per orientation two cuts:
// the nearest in a plane below the vertex and the nearest in a plane above it. When both exist (the planes
// are parallel), the vertex's 2D cone is the blend of theirs at its own height (blend_wedges: each wedge end
// interpolated linearly in the vertex's offset between the two planes), so the slice point's offset from
// the vertex cancels to first order and the cone moves continuously as the vertex moves between planes;
// where the two cones cannot be matched (a wedge appears or vanishes between the planes), the cone of the
// nearer plane.
#include "static_core/cone_rules.hpp"

namespace pleat::rules {

extern const ConeStorageRule kInterpolatedOnFan{"interpolated-on-fan",
                                                "the same cuts as aimed-on-fan, their wedge angles blended",
                                                ConeStorageRule::Offer::BothEndpoints,
                                                ConeStorageRule::Keep::NearestBelowAndAbove,
                                                ConeStorageRule::Combine::Blend,
                                                false};

}  // namespace pleat::rules
