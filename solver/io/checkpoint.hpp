// Checkpoints: the complete state needed to continue a run bit for bit. Written to a
// temporary file that is renamed over the previous checkpoint only once it is complete,
// so a crash never leaves a corrupt last checkpoint.
#pragma once

#include "bodies/body.hpp"
#include "parallel/decomposition.hpp"
#include "time/flow_state.hpp"

#include <filesystem>

namespace efsi {

struct RunClock {
    real next_fields_time = 0; ///< simulated time of the next snapshot
};

/// Bodies are stored with their patch box; on reading, each body of `bodies` (already
/// constructed from the case) is re-allocated on its stored patch and filled.
void write_checkpoint(const std::filesystem::path& file, const Decomposition& dec,
                      const FlowState& s, const RunClock& clock,
                      const std::vector<Body*>& bodies = {});
void read_checkpoint(const std::filesystem::path& file, const Decomposition& dec, FlowState& s,
                     RunClock& clock, const std::vector<Body*>& bodies = {});

} // namespace efsi
