#pragma once
/// Parsers for the parts of a scene file; each records every problem in the Checker and returns
/// a spec with defaults wherever a value was absent or invalid.
#include <string>
#include <vector>

#include "scene/checker.hpp"
#include "scene/spec.hpp"

namespace dexcloth::scene {

/// `{"translation": [x,y,z], "rotation_deg": [rx,ry,rz]}`, both optional.
TransformSpec parse_transform(Checker& c, const Json& v, const Pointer& at);

/// `[{"t": s, "translation": [..], "rotation_deg": [..]}, ...]` with strictly increasing t;
/// `rotation_deg` is allowed only when `with_rotation` (obstacles, not handles).
std::vector<KeyframeSpec> parse_motion(Checker& c, const Json& v, const Pointer& at,
                                       bool with_rotation);

/// One entry of `/cloths`.
ClothSpec parse_cloth(Checker& c, const Json& v, const Pointer& at);

/// One entry of `/obstacles`.
ObstacleSpec parse_obstacle(Checker& c, const Json& v, const Pointer& at);

/// One entry of `/probes`; `cloth_names` are the cloths the probe may refer to.
ProbeSpec parse_probe(Checker& c, const Json& v, const Pointer& at,
                      const std::vector<std::string>& cloth_names);

/// Which of `options` object `obj` has; reports unless there is exactly one. All present
/// options are returned so each can still be checked.
std::vector<std::string> one_of(Checker& c, const Json& obj, const Pointer& at,
                                const std::vector<std::string_view>& options);

/// A named item of a list, for the uniqueness check.
struct NamedAt {
  std::string name;  ///< the item's name ("" when it had none: skipped)
  Pointer at;        ///< pointer to the item
};

/// Reports every item whose name an earlier item already uses; `what` is "cloth", "obstacle", ...
void check_unique_names(Checker& c, const std::vector<NamedAt>& items, const std::string& what);

}  // namespace dexcloth::scene
