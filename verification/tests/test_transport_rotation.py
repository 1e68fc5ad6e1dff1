"""A rigid rotation carries Gs without straining it: the spurious area ratio J(Gs) != 1 that
the transport alone creates must shrink at about second order (efsi_transport_study
--flow rotation; 2D, sphere of diameter 0.6 turned by one radian). Skipped when the study
binary has not been built."""
import json
import math
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
EXE = REPO / "build" / "bin" / "efsi_transport_study"

pytestmark = pytest.mark.skipif(not EXE.exists(), reason=f"{EXE} not built")


def run(cells: int) -> dict:
    out = subprocess.run([str(EXE), "--flow", "rotation", "--dim", "2", "--cells", str(cells),
                          "--time", "1"], capture_output=True, text=True, timeout=600, check=True)
    return json.loads(out.stdout)


def test_rotation_creates_no_strain_in_the_limit():
    coarse, fine = run(32), run(64)
    # B starts at I and a rotation keeps F F^T = I: Heun's method keeps it to round-off.
    assert fine["B_error_max"] < 1e-12, fine
    order_j = math.log2(coarse["J_error_rms"] / fine["J_error_rms"])
    order_gs = math.log2(coarse["Gs_error_L2"] / fine["Gs_error_L2"])
    assert order_j >= 1.5, (coarse, fine)
    assert order_gs >= 1.5, (coarse, fine)
    assert fine["J_error_rms"] < 5e-3, fine  # 19 cells per diameter (2.4e-3 measured)
