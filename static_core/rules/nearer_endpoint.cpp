// The paper's storage rule (Stewart 1999 §2.4; docs/method.md §7): a slice vertex's cone goes to the nearer
// endpoint of its edge only; per plane, side and vertex the nearest offer is kept, and a vertex keeps one
// cone from every plane that offered it one.
#include "static_core/cone_rules.hpp"

namespace pleat::rules {

extern const ConeStorageRule kNearerEndpoint{
    "nearer-endpoint",
    "the paper's: every plane's cut on edges the vertex is nearer to",
    ConeStorageRule::Offer::NearerEndpoint,
    ConeStorageRule::Keep::EveryPlane,
    ConeStorageRule::Combine::None,
    false};

}  // namespace pleat::rules
