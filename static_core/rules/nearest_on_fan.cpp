// The nearest-on-fan storage rule (docs/method.md §7): a slice vertex's cone goes to both endpoints of its
// edge; per orientation, side and vertex only the nearest offer over all planes of the orientation is kept
// (ties: the lower plane, then the lower slice vertex). A vertex gets a cone in every orientation whose
// planes cut its own edges, from the nearest such cut, so far fewer vertices borrow a neighbour's, and
// parallel planes' cones taken from different points are not merged into one vertex.
#include "static_core/cone_rules.hpp"

namespace pleat::rules {

extern const ConeStorageRule kNearestOnFan{"nearest-on-fan",
                                           "the nearest cut of its own edges per orientation",
                                           ConeStorageRule::Offer::BothEndpoints,
                                           ConeStorageRule::Keep::Nearest,
                                           ConeStorageRule::Combine::None,
                                           false};

}  // namespace pleat::rules
