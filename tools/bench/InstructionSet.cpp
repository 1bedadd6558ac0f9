#include "tools/bench/InstructionSet.h"

namespace strata::bench {

std::string InstructionSet() {
  std::string name;
#if defined(__x86_64__)
  name = "x86-64";
#elif defined(__aarch64__)
  name = "AArch64";
#else
  name = "other";
#endif
  // In the order the levels add them (x86-64, -v2, -v3, -v4).
  constexpr bool kHas[] = {
#ifdef __SSE2__
      true,
#else
      false,
#endif
#ifdef __SSE4_2__
      true,
#else
      false,
#endif
#ifdef __AVX__
      true,
#else
      false,
#endif
#ifdef __AVX2__
      true,
#else
      false,
#endif
#ifdef __FMA__
      true,
#else
      false,
#endif
#ifdef __AVX512F__
      true,
#else
      false,
#endif
  };
  constexpr const char* kNames[] = {"SSE2", "SSE4.2", "AVX", "AVX2", "FMA", "AVX-512"};
  for (std::size_t i = 0; i < std::size(kNames); ++i)
    if (kHas[i]) name += std::string(" ") + kNames[i];
  return name;
}

}  // namespace strata::bench
