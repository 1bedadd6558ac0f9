// JointParser: one entry of a scene file's "constraints" array into the JointSettings of its type (fixed,
// point, distance, hinge, slider, swing_twist), its bodies named by the scene's body names. Angles in the
// file are degrees. Errors name the file, the JSON path and why. Stateless; any thread.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "assets/scene/SceneJsonReader.h"
#include "assets/scene/SceneLoader.h"

namespace strata {

/// Parses the joint `json` (at `reader`'s path) between bodies of `bodies`, found by name in `body_index`.
Result<SceneConstraint> ParseConstraint(const SceneJsonReader& reader, const SceneJson& json,
                                        const std::map<std::string, int>& body_index,
                                        const std::vector<SceneBody>& bodies);

}  // namespace strata
