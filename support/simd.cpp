#include "cshapes/support/simd.h"

#include <atomic>
#include <cstdlib>

#include "cshapes/support/error.h"

namespace cshapes {

namespace {

constexpr SimdTarget kAll[] = {SimdTarget::Baseline, SimdTarget::Avx2, SimdTarget::Avx512};

// -1: not chosen yet; otherwise a SimdTarget. Chosen once per process (or by set_simd_target).
std::atomic<int> g_target{-1};
std::atomic<bool> g_forced_by_environment{false};

// The default: AVX2 where the CPU has it, else the baseline. AVX-512 only when asked for: its kernels were
// measured no faster than AVX2's, and the lower clock of 512-bit instructions slowed the code around them
// (docs/benchmarks.md, the rows per instruction set).
SimdTarget default_target() {
  return simd_supported(SimdTarget::Avx2) ? SimdTarget::Avx2 : SimdTarget::Baseline;
}

std::string list(const std::vector<SimdTarget>& targets) {
  std::string out;
  for (SimdTarget t : targets) out += (out.empty() ? "" : ", ") + std::string(to_string(t));
  return out;
}

}  // namespace

const char* to_string(SimdTarget target) {
  switch (target) {
    case SimdTarget::Baseline:
      return "baseline";
    case SimdTarget::Avx2:
      return "avx2";
    case SimdTarget::Avx512:
      return "avx512";
  }
  return "?";
}

bool simd_supported(SimdTarget target) {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  switch (target) {
    case SimdTarget::Baseline:
      return true;
    case SimdTarget::Avx2:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case SimdTarget::Avx512:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
             __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw");
  }
  return false;
#else
  return target == SimdTarget::Baseline;
#endif
}

std::vector<SimdTarget> supported_simd_targets() {
  std::vector<SimdTarget> out;
  for (SimdTarget t : kAll)
    if (simd_supported(t)) out.push_back(t);
  return out;
}

SimdTarget parse_simd_target(const std::string& name, const std::string& what) {
  for (SimdTarget t : kAll)
    if (name == to_string(t)) return t;
  throw Error(what + "=" + name + ": unknown instruction set; expected baseline, avx2 or avx512");
}

void set_simd_target(SimdTarget target) {
  CSHAPES_REQUIRE(simd_supported(target), "instruction set ", to_string(target),
                  " is not supported by this CPU (it supports ", list(supported_simd_targets()), ")");
  g_target.store(static_cast<int>(target));
  g_forced_by_environment.store(false);
}

SimdTarget simd_target() {
  const int chosen = g_target.load(std::memory_order_relaxed);
  if (chosen >= 0) return static_cast<SimdTarget>(chosen);
  SimdTarget target = default_target();
  bool forced = false;
  if (const char* env = std::getenv("CSHAPES_SIMD"); env && *env) {
    target = parse_simd_target(env, "CSHAPES_SIMD");
    CSHAPES_REQUIRE(simd_supported(target), "CSHAPES_SIMD=", env,
                    ": this CPU does not support it (it supports ", list(supported_simd_targets()), ")");
    forced = true;
  }
  int expected = -1;
  if (g_target.compare_exchange_strong(expected, static_cast<int>(target))) g_forced_by_environment = forced;
  return static_cast<SimdTarget>(g_target.load());
}

std::string simd_description() {
  const SimdTarget target = simd_target();
  const std::string cpu = list(supported_simd_targets());
  if (g_forced_by_environment)
    return std::string(to_string(target)) + " (forced by CSHAPES_SIMD; this CPU: " + cpu + ")";
  if (target != default_target()) return std::string(to_string(target)) + " (forced; this CPU: " + cpu + ")";
  return std::string(to_string(target)) + " (the default; this CPU: " + cpu + ")";
}

}  // namespace cshapes
