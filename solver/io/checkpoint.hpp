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
///
/// Every dataset carries a rank-count independent checksum (attribute "checksum"), the
/// file carries the case fingerprint (case_fingerprint()) and a checksum of its scalar
/// attributes. The file is written to `<file>.tmp`, closed, reopened and verified (every
/// dataset present and reading back to the checksum of the values in memory), and only
/// then renamed over `file`. Any failure removes the tmp file, leaves `file` as it was,
/// and throws IoError naming the last good checkpoint.
void write_checkpoint(const std::filesystem::path& file, const Decomposition& dec,
                      const FlowState& s, const RunClock& clock,
                      const std::vector<Body*>& bodies = {}, const std::string& fingerprint = "");
/// Refuses (InputError, naming the problem) a file that is not a checkpoint of this format,
/// was written for another case (fingerprint; skipped when `fingerprint` is empty), or
/// whose attributes or datasets do not match their checksums (corrupted, truncated).
void read_checkpoint(const std::filesystem::path& file, const Decomposition& dec, FlowState& s,
                     RunClock& clock, const std::vector<Body*>& bodies = {},
                     const std::string& fingerprint = "");

} // namespace efsi
