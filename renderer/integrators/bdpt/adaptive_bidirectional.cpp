#include "integrators/bdpt/adaptive_bidirectional.h"

#include <stdexcept>

#include "integrators/bdpt/bidirectional_tracer.h"
#include "integrators/pt/path_tracer.h"

namespace veach {

void AdaptiveBidirectional::render_tile(const RenderScene& rs, const Tile& tile, uint32_t sample_begin,
                                        uint32_t sample_end, Film& film, ThreadStats& stats) const {
    if (!m_chosen) throw std::logic_error("AdaptiveBidirectional: a tile before the first pass began");
    m_chosen->render_tile(rs, tile, sample_begin, sample_end, film, stats);
}

void AdaptiveBidirectional::begin_pass(const RenderScene& rs, uint32_t begin, uint32_t end, Film& film) {
    if (!m_chosen) {
        m_choice = choose_strategies(rs, m_settings, film);
        if (m_choice.path_tracer) {
            m_chosen = std::make_unique<PathTracer>(m_settings);
        } else {
            BdptOptions options;
            options.strategies = m_choice.mask;
            m_chosen = std::make_unique<BidirectionalTracer>(m_settings, options);
        }
    }
    m_chosen->begin_pass(rs, begin, end, film);
}

void AdaptiveBidirectional::end_pass(const RenderScene& rs, uint32_t begin, uint32_t end, Film& film) {
    if (m_chosen) m_chosen->end_pass(rs, begin, end, film);
}

}  // namespace veach
