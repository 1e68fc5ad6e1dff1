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
