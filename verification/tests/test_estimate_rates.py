"""The rates `efsi check` estimates a run with (solver/simulation/run_estimate.cpp) are the
ones the blood_capillary study measured and stored (verification/results/blood_capillary):
no rate in the C++ is typed by hand or left stale."""
import json
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
RESULT = REPO / "verification" / "results" / "blood_capillary" / "result.json"
THROUGHPUT = REPO / "verification" / "results" / "throughput" / "result.json"

# constant in run_estimate.cpp -> (result, metric, transform)
CONSTANTS = {
    "PROCESS_BYTES": (RESULT, "rate_process_base_bytes", lambda v: v),
    "FLOW_BYTES_PER_CELL": (RESULT, "rate_flow_bytes_per_cell", lambda v: v),
    "FLOW_BYTES_PER_CELL_HYPRE": (RESULT, "rate_flow_bytes_per_cell_hypre", lambda v: v),
    "FLOW_SECONDS_HYPRE": (RESULT, "rate_flow_seconds_per_cell_step_hypre", lambda v: v),
    "SOLID_BYTES": (RESULT, "rate_solid_bytes_per_patch_cell", lambda v: v),
    "SOLID_SECONDS": (RESULT, "rate_solid_seconds_per_patch_cell_step", lambda v: v),
    "MEMBRANE_BYTES": (RESULT, "rate_membrane_bytes_per_patch_cell", lambda v: v),
    "MEMBRANE_SECONDS": (RESULT, "rate_membrane_seconds_per_patch_cell_step", lambda v: v),
    "FLOW_SECONDS_FFT": (THROUGHPUT, "cell_updates_per_second_1rank_128", lambda v: 1 / v),
}


def constants():
    text = (REPO / "solver" / "simulation" / "run_estimate.cpp").read_text()
    out = {}
    for name, expr in re.findall(r"constexpr double (\w+) = ([^;]+);", text):
        out[name] = eval(expr, {"__builtins__": {}})  # numbers and 1 / x only
    return out


@pytest.mark.skipif(not RESULT.exists(), reason="no stored blood_capillary result")
def test_estimate_rates_are_the_stored_measurements():
    have = constants()
    for name, (path, metric, f) in CONSTANTS.items():
        measured = f(json.loads(path.read_text())["metrics"][metric])
        assert name in have, f"run_estimate.cpp has no {name}"
        # The C++ holds them to 3 significant digits.
        assert abs(have[name] - measured) <= 5e-3 * abs(measured), (name, have[name], measured)


def test_seam_copies_are_taken_out_before_the_patch_bytes():
    """The copies across the periodic x seam are the grid's size: estimate_rates removes each
    run's own (summary.json seam_copy_bytes_max_rank) from its peak memory, so they are not
    charged to the few platelet patch cells (run_estimate.cpp counts them on their own)."""
    import sys
    sys.path.insert(0, str(REPO / "verification" / "studies"))
    from blood_capillary import estimate_rates

    def run(rss, seam, platelets, cells, seconds=1.0):
        bodies = ([{"name": f"platelet_{i}", "patch_cells": 1000} for i in range(platelets)]
                  + [{"name": f"rbc_{i}", "patch_cells": 5000} for i in range(cells)])
        s = {"ranks": 1, "cells": 8000, "steps": 10, "peak_rss_bytes_max_rank": rss,
             "stages": {"bodies_vof": seconds, "viscous_solve": 2.0}, "bodies": bodies}
        if seam is not None:
            s["seam_copy_bytes_max_rank"] = seam
        return s

    plasma = run(1.0e8, 0.0, 0, 0)
    platelets = run(1.0e8 + 4 * 1000 * 600 + 3.0e7, 3.0e7, 4, 0)
    cells = run(platelets["peak_rss_bytes_max_rank"] + 10 * 5000 * 700 + 1.0e7, 4.0e7, 4, 10)
    r = estimate_rates({"plasma": plasma, "platelets": platelets, "cells": cells})
    assert r["rate_solid_bytes_per_patch_cell"] == pytest.approx(600)
    assert r["rate_membrane_bytes_per_patch_cell"] == pytest.approx(700)
    assert r["seam_copy_bytes_platelets"] == 3.0e7 and r["seam_copy_bytes_cells"] == 4.0e7
    # Without the key (runs made before it existed) the copies stay in the patches' bytes.
    before = {k: v for k, v in platelets.items() if k != "seam_copy_bytes_max_rank"}
    old = estimate_rates({"plasma": plasma, "platelets": before, "cells": cells})
    assert old["rate_solid_bytes_per_patch_cell"] == pytest.approx(600 + 3.0e7 / 4000)
