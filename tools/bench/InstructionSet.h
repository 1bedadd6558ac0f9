// InstructionSet: the x86 instruction-set extensions this binary was compiled to use (-march), so every
// benchmark figure can say which build made it. Pure; any thread.
#pragma once

#include <string>

namespace strata::bench {

/// The architecture and its vector extensions the compiler was allowed to use, e.g. "x86-64 SSE2" for the
/// portable build or "x86-64 SSE2 SSE4.2 AVX AVX2 FMA" for -DSTRATA_ARCH=x86-64-v3.
std::string InstructionSet();

}  // namespace strata::bench
