// Checkpoints: the complete state needed to continue a run bit for bit. Written to a
// temporary file that is renamed over the previous checkpoint only once it is complete,
// so a crash never leaves a corrupt last checkpoint.
#pragma once

#include "bodies/body.hpp"
#include "core/state_record.hpp"
#include "parallel/decomposition.hpp"
#include "time/flow_state.hpp"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace efsi {

struct RunClock {
    real next_fields_time = 0; ///< simulated time of the next snapshot
};

/// A record of state that is not a grid field (core/state_record.hpp), stored as group
/// /<name> of the checkpoint: one dataset per array, each with its checksum, and the
/// record's description as the group's attribute "description".
using NamedRecord = std::pair<std::string, StateRecord*>;

/// Bodies are stored with their patch box; on reading, each body of `bodies` (already
/// constructed from the case) is re-allocated on its stored patch and filled.
///
/// Every dataset carries a rank-count independent checksum (attribute "checksum"), the
/// file carries the case fingerprint (case_fingerprint()) and a checksum of its scalar
/// attributes. The file is written to `<file>.tmp`, closed, reopened and verified (every
/// dataset present and reading back to the checksum of the values in memory), and only
/// then renamed over `file`. Any failure removes the tmp file, leaves `file` as it was,
/// and throws IoError naming the last good checkpoint.
///
/// `records` (e.g. the adhesion's receptors and bonds) hold the same values on every rank;
/// rank 0 writes them, and every rank reads all of them back, so they restart on any rank
/// count.
void write_checkpoint(const std::filesystem::path& file, const Decomposition& dec,
                      const FlowState& s, const RunClock& clock,
                      const std::vector<Body*>& bodies = {}, const std::string& fingerprint = "",
                      const std::vector<NamedRecord>& records = {});
/// Refuses (InputError, naming the problem) a file that is not a checkpoint of this format,
/// lacks one of `records` or holds a record not asked for (before the fingerprint, so
/// that this is what the message says), was written for another case (fingerprint;
/// skipped when `fingerprint` is empty), or whose attributes or datasets do not match
/// their checksums (corrupted, truncated). Each of `records` is filled from its group
/// (its description is that of the caller, used in the messages).
void read_checkpoint(const std::filesystem::path& file, const Decomposition& dec, FlowState& s,
                     RunClock& clock, const std::vector<Body*>& bodies = {},
                     const std::string& fingerprint = "",
                     const std::vector<NamedRecord>& records = {});

} // namespace efsi
