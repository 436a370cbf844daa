// The instruction set the hot kernels run with, chosen at run time.
//
// One binary carries each hot kernel (the Coulomb near field and direct float sum, the SMACOF pass, the
// metric projection sweep, the FMM's M2L, the heat method's solves and divergence, classical MDS's product)
// compiled for several x86-64 instruction sets: Baseline (SSE2, every x86-64), Avx2 (AVX2 + FMA), Avx512
// (AVX-512 F/VL/DQ/BW). The default is Avx2 where the CPU has it, else Baseline: AVX-512's kernels were
// measured no faster than AVX2's, and the lower clock of 512-bit instructions slows the code around them
// (docs/benchmarks.md), so AVX-512 runs only when asked for. The environment variable CSHAPES_SIMD=baseline|avx2|avx512 forces one (for tests and
// comparisons); forcing one the CPU lacks is an error, never a silent fallback.
//
// Results: each target is deterministic (the same bytes for any thread count). The Coulomb method's kernels
// give the same bytes under every target (the same IEEE operations in the same order: no fused multiply-adds,
// the same `rsqrtps` estimate); the SMACOF pass differs in its last bits between the baseline (an exact
// square root) and the AVX targets (the estimate, fused multiply-adds). docs/benchmarks.md states the bound
// per method and tests/simd_test.cpp checks it. The estimate's tables differ between processor makers.
#pragma once

#include <string>
#include <vector>

namespace cshapes {

enum class SimdTarget { Baseline = 0, Avx2 = 1, Avx512 = 2 };

// "baseline", "avx2", "avx512".
const char* to_string(SimdTarget target);

// Whether this CPU (and operating system) can run the target's kernels.
bool simd_supported(SimdTarget target);

// The targets this CPU supports, lowest first (always starts with Baseline).
std::vector<SimdTarget> supported_simd_targets();

// The target the kernels use: set_simd_target's, else CSHAPES_SIMD's, else the default (above). Throws
// cshapes::Error naming the variable when CSHAPES_SIMD holds an unknown name or a target this CPU lacks.
SimdTarget simd_target();

// Forces the kernels' target for this process (tests, `bench --simd`). Throws when the CPU lacks it.
void set_simd_target(SimdTarget target);

// Parses "baseline", "avx2" or "avx512"; throws listing them otherwise. `what` names the source in the
// message (e.g. "CSHAPES_SIMD").
SimdTarget parse_simd_target(const std::string& name, const std::string& what);

// One line for --version and reports: "avx2 (the default; this CPU: baseline, avx2, avx512)" or
// "avx512 (forced by CSHAPES_SIMD; this CPU: baseline, avx2, avx512)".
std::string simd_description();

}  // namespace cshapes
