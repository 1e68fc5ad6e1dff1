"""The predictor of a flow with pinned solids (capillary_coarse's vessel wall) as a row sweep
(session 48) against the pointwise loop it replaces: two efsi binaries, 10 steps of
cases/capillary_coarse from one checkpoint at step 10, alternated twice on 1 rank; the
largest relative difference of every dataset of their checkpoints and the stage times.
Writes result.md beside this script.

    /usr/bin/python3 verification/records/blood_capillary/pinned_predictor_s48/measure.py \
        OLD_EFSI NEW_EFSI START_CHECKPOINT WORKDIR      (from the repository root)

START_CHECKPOINT: a checkpoint of cases/capillary_coarse at step 10 with output.fields=false
and output.diagnostics_every=5 (band_transport_s48/measure.py makes one, WORKDIR/start).
"""

import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from capillary_ab import stage_table  # noqa: E402

old, new, start, work = sys.argv[1:5]
stage_table(old, new, start, work, "predictor", ("pointwise (old)", "row sweep (new)"),
            "The predictor with pinned solids as a row sweep", "predictor",
            pathlib.Path(__file__).parent / "result.md")
