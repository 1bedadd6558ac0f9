#include "navmesh/NavMeshServiceConfig.h"

#include <cmath>
#include <set>
#include <string>

namespace strata::navmesh {

Status NavMeshServiceConfig::Validate() const {
  if (Status status = settings.Validate(); !status.ok()) return status;
  if (profiles.size() > static_cast<std::size_t>(kMaxProfiles))
    return MakeError(ErrorCode::kInvalidArgument, "navmesh service: at most " + std::to_string(kMaxProfiles) +
                                                      " agent profiles (got " +
                                                      std::to_string(profiles.size()) + ")");
  std::set<std::string> names;
  for (const AgentProfile& profile : profiles) {
    if (Status valid = profile.Validate(settings); !valid) return valid;
    if (!names.insert(profile.name).second)
      return MakeError(ErrorCode::kInvalidArgument,
                       "navmesh service: two agent profiles are named '" + profile.name + "'");
  }
  if (worker_threads < 1 || worker_threads > kMaxWorkerThreads)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh service: worker_threads must be in [1, " +
                                                      std::to_string(kMaxWorkerThreads) + "]");
  if (!std::isfinite(move_threshold) || move_threshold < 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh service: move_threshold must be >= 0");
  if (std::isnan(filter.min_dynamic_size) || filter.min_dynamic_size < 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh service: filter.min_dynamic_size must be >= 0");
  if (thread_niceness < 0 || thread_niceness > 19)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh service: thread_niceness must be in [0, 19]");
  if (rebuild_delay.count() < 0 || scan_interval.count() < 1)
    return MakeError(ErrorCode::kInvalidArgument,
                     "navmesh service: rebuild_delay must be >= 0 and scan_interval >= 1 ms");
  return Status::Ok();
}

}  // namespace strata::navmesh
