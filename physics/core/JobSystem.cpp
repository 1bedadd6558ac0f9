#include "physics/core/JobSystem.h"

#include "physics/core/ThreadPoolJobSystem.h"
#ifdef STRATA_HAVE_TBB
#include "physics/core/TbbJobSystem.h"
#endif

namespace strata {

std::unique_ptr<JobSystem> MakeDefaultJobSystem(int thread_count) {
#ifdef STRATA_HAVE_TBB
  return std::make_unique<TbbJobSystem>(thread_count);
#else
  return std::make_unique<ThreadPoolJobSystem>(thread_count);
#endif
}

}  // namespace strata
