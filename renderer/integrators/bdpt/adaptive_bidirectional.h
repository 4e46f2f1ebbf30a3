// The default integrator (`auto`): bidirectional path tracing with the strategy families each
// render needs. Before its first pass it asks strategy_selection.h which families pay for
// themselves on this scene and camera, then renders every pass with exactly those, weighted by
// the power heuristic over them: BidirectionalTracer with that set, or PathTracer when the set is
// the path tracer's (emission and light samples alone).
#pragma once

#include <memory>

#include "integrators/bdpt/strategy_selection.h"
#include "integrators/integrator.h"

namespace veach {

class AdaptiveBidirectional final : public Integrator {
public:
    explicit AdaptiveBidirectional(const RenderSettings& settings) : m_settings(settings) {}

    void render_tile(const RenderScene& rs, const Tile& tile, uint32_t sample_begin, uint32_t sample_end, Film& film,
                     ThreadStats& stats) const override;
    // The first call chooses (a resumed render or a part chooses as the whole render did).
    void begin_pass(const RenderScene& rs, uint32_t begin, uint32_t end, Film& film) override;
    void end_pass(const RenderScene& rs, uint32_t begin, uint32_t end, Film& film) override;
    std::string strategies() const override { return m_chosen ? describe(m_choice) : std::string(); }

    const StrategyChoice& choice() const { return m_choice; }

private:
    RenderSettings m_settings;
    StrategyChoice m_choice;
    std::unique_ptr<Integrator> m_chosen;
};

}  // namespace veach
