// The aimed-on-fan storage rule, the default (docs/method.md §7): as interpolated-on-fan, but the cones are
// seen from the vertex itself (aim_wedges): a wedge end bounded by a slice point (its reach) is a point of
// the horizon, so the end becomes the direction from the vertex to that point — for two planes, to the blend
// of their two horizon points at the vertex's height. This removes the slice point's offset from the vertex
// within the plane as well as across it. A vertex's own cones are those of its fan (fan_cone.hpp).
#include "static_core/cone_rules.hpp"

namespace pleat::rules {

extern const ConeStorageRule kAimedOnFan{
    "aimed-on-fan",
    "per orientation, the cuts of a vertex's own edges nearest below and above it, their horizon points "
    "blended at its height and aimed at from the vertex",
    ConeStorageRule::Offer::BothEndpoints,
    ConeStorageRule::Keep::NearestBelowAndAbove,
    ConeStorageRule::Combine::Aim,
    true};

}  // namespace pleat::rules
