// BDPT's strategies grouped by what they cost and what they need, so that a render can leave out a
// group that does not pay for itself (bdpt/strategy_selection.h):
//   emission     s = 0: the camera subpath finds an emitter (no ray of its own)
//   light sample s = 1, t >= 2: next-event estimation (a shadow ray per camera vertex)
//   camera       t = 1: light tracing, a light subpath vertex joined to the camera (a splat)
//   connection   s, t >= 2: the two subpaths' end vertices joined (a shadow ray per pair)
// The last two need a light subpath. A set of families is a bit mask; the MIS weights of a render
// that uses a set are the power heuristic over exactly the strategies in it (mis_weight.h).
#pragma once

#include <cstdint>

namespace veach {

enum class StrategyFamily : uint8_t { Emission = 0, LightSample = 1, Camera = 2, Connection = 3 };
constexpr int k_strategy_families = 4;

using StrategyMask = uint8_t;
constexpr StrategyMask family_bit(StrategyFamily f) { return static_cast<StrategyMask>(1u << static_cast<int>(f)); }
constexpr StrategyMask k_all_strategies = 0xF;

constexpr int strategy_family_index(int s, int t) { return s == 0 ? 0 : t == 1 ? 2 : s == 1 ? 1 : 3; }
constexpr bool strategy_in(StrategyMask mask, int s, int t) { return (mask >> strategy_family_index(s, t)) & 1u; }
// Whether the set needs a light subpath traced.
constexpr bool needs_light_subpath(StrategyMask mask) {
    return (mask & (family_bit(StrategyFamily::Camera) | family_bit(StrategyFamily::Connection))) != 0;
}

}  // namespace veach
