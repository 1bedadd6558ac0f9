// JointParser: one entry of a scene file's "constraints" array into a JointDescription of its kind (fixed,
// point, distance, hinge, slider, swing_twist), its bodies named by the scene's body names, checked as the
// joint Strata would make. Angles in the
// file are degrees. Errors name the file, the JSON path and why. Stateless; any thread.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "assets/scene/SceneDescription.h"
#include "assets/scene/SceneJsonReader.h"

namespace strata {

/// Parses the joint `json` (at `reader`'s path) between bodies of `bodies`, found by name in `body_index`.
Result<JointDescription> ParseConstraint(const SceneJsonReader& reader, const SceneJson& json,
                                         const std::map<std::string, int>& body_index,
                                         const std::vector<BodyDescription>& bodies);

}  // namespace strata
