"""Our output read with the tools people use (issue 23, item 6): a short run with the three
kinds of body (passive, solid, membrane) on 2 ranks and a small 3D run, opened with meshio's
TimeSeriesReader (meshio.read reads one grid only) and h5py: every field's shape, centring
and units attributes, `step` an integer, the XInclude namespace ParaView's legacy reader
needs, and docs/output.md naming every field. Skipped when build/bin/efsi is not built."""
import os
import re
import shutil
import subprocess
from pathlib import Path

import h5py
import meshio
import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
EFSI = Path(os.environ.get("EFSI_BIN", REPO / "build" / "bin" / "efsi"))
pytestmark = pytest.mark.skipif(not EFSI.exists(), reason=f"{EFSI} not built")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_mpi_yield_when_idle="1")

RUNS = {
    # 2D, three bodies: phi_<name>, <name>_B_* (solid), <name>_Gs_* (membrane)
    # (split along x: the membrane's normal extension needs blocks 10 cells wide)
    "bodies_2d": ("body_translation", 2, ["grid.cells=[32,16,1]", "grid.length=[2.0,1.0,0.0625]",
                                          "parallel.ranks=[2,1,1]",
                                          "time.max_steps=3", "output.fields_interval=0.01"],
                  (32, 16, 1)),
    "box_3d": ("lid_cavity", 1, ["grid.cells=[6,5,4]", "grid.length=[1.2,1.0,0.8]",
                                 "boundary.z_low=wall", "boundary.z_high=wall", "time.max_steps=2"],
               (6, 5, 4)),
}


@pytest.fixture(scope="module", params=sorted(RUNS))
def run(request, tmp_path_factory):
    case, ranks, sets, cells = RUNS[request.param]
    out = tmp_path_factory.mktemp(request.param)
    cmd = ([] if ranks == 1 else ["mpiexec", "-np", str(ranks), "--oversubscribe"])
    cmd += [str(EFSI), "run", str(REPO / "cases" / case), "--output", str(out), "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    return out, cells


def expected(name, dim):
    """(units, centring) every dataset of a snapshot must carry."""
    if name == "pressure":
        return "Pa", "cell"
    if name == "velocity":
        return "m/s", "cell"
    if name.startswith("faces_"):
        return "m/s", name[-1].replace("u", "x").replace("v", "y").replace("w", "z") + "_face"
    if name.startswith("phi_") or re.search(r"_(B|Gs)_[xyz]{2}$", name):
        return "1", "cell"
    if name.endswith("_kappa_R"):
        return "1/m", "cell"
    raise AssertionError(f"undocumented dataset {name}")


def text(attr):
    return attr.decode() if isinstance(attr, bytes) else str(attr)


def test_meshio_time_series(run):
    out, cells = run
    n = int(np.prod(cells))
    xdmf = out / "fields" / "fields.xdmf"
    assert 'xmlns:xi="http://www.w3.org/2001/XInclude"' in xdmf.read_text()
    with meshio.xdmf.TimeSeriesReader(str(xdmf)) as reader:
        points, blocks = reader.read_points_cells()
        assert sum(len(b.data) for b in blocks) == n
        assert reader.num_steps >= 2
        for k in range(reader.num_steps):
            t, _, cell_data = reader.read_data(k)
            assert cell_data["velocity"][0].shape == (n, 3)
            for name, (arr,) in cell_data.items():
                if name != "velocity":
                    assert arr.shape in [(n,), (n, 1)], (name, arr.shape)


def test_image_xdmf(run):
    """fields_image.xdmf: the same snapshots on a 3DCoRectMesh with the grid's origin and
    spacing (read by ParaView's XDMF readers as image data)."""
    out, cells = run
    text = (out / "fields" / "fields_image.xdmf").read_text()
    assert 'xmlns:xi="http://www.w3.org/2001/XInclude"' in text
    nz, ny, nx = cells[2], cells[1], cells[0]
    assert f'TopologyType="3DCoRectMesh" Dimensions="{nz + 1} {ny + 1} {nx + 1}"' in text
    assert text.count("<Time ") == len(list((out / "fields").glob("fields_*.h5")))
    assert f'Dimensions="{nz} {ny} {nx} 3"' in text  # the velocity


def test_h5_fields_carry_units_and_centring(run):
    out, cells = run
    n = int(np.prod(cells))
    dim = 2 if cells[2] == 1 else 3
    files = sorted((out / "fields").glob("fields_*.h5"))
    assert files
    names = set()
    for path in files:
        with h5py.File(path, "r") as f:
            assert f.attrs["step"].dtype.kind == "i" and f.attrs["time"].dtype.kind == "f"
            for name, ds in f.items():
                names.add(name)
                units, centring = expected(name, dim)
                assert text(ds.attrs["units"]) == units, name
                assert text(ds.attrs["centring"]) == centring, name
                if name.startswith("faces_"):
                    assert ds.shape == (cells[2], cells[1], cells[0]), name
                elif name == "velocity":
                    assert ds.shape == (n, 3)
                else:
                    assert ds.shape == (n,), name
    assert {"pressure", "velocity", "faces_u", "faces_v"} <= names
    assert ("faces_w" in names) == (dim == 3)
    if "bodies" in out.name:
        assert any(re.match(r"phi_", s) for s in names)
        assert any(re.search(r"_B_xx$", s) for s in names)
        assert any(re.search(r"_Gs_xx$", s) for s in names)
    with h5py.File(out / "fields" / "mesh.h5", "r") as f:
        assert text(f["geometry"].attrs["units"]) == "m"


def test_docs_list_every_field():
    doc = (REPO / "docs" / "output.md").read_text()
    for word in ("pressure", "velocity", "faces_u", "phi_<name>", "<name>_B_", "<name>_Gs_",
                 "<name>_kappa_R", "units", "centring", "TimeSeriesReader", "XDMF"):
        assert word in doc, word


PROBE = """
import sys
from paraview.simple import XDMFReader, Xdmf3ReaderS
for path in sys.argv[1:]:
    for name in ("legacy", "xdmf3"):
        r = XDMFReader(FileNames=[path]) if name == "legacy" else Xdmf3ReaderS(FileName=[path])
        t = r.TimestepValues
        r.UpdatePipeline(t[-1] if t else 0.0)
        names = sorted(r.CellData.GetArray(i).GetName() for i in range(len(r.CellData)))
        print("READ", name, path.split("/")[-1], r.GetDataInformation().GetNumberOfCells(),
              ",".join(names))
"""


@pytest.mark.skipif(not shutil.which("pvbatch"), reason="ParaView (pvbatch) not installed")
def test_paraview_readers(run, tmp_path):
    """ParaView's legacy XDMF reader (which crashed on the https XInclude namespace) and its
    Xdmf3 reader open both XDMF files with every cell of the grid and the fields."""
    out, cells = run
    probe = tmp_path / "probe.py"
    probe.write_text(PROBE)
    files = [str(out / "fields" / n) for n in ("fields.xdmf", "fields_image.xdmf")]
    p = subprocess.run(["pvbatch", str(probe), *files], capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    lines = [line.split() for line in p.stdout.splitlines() if line.startswith("READ")]
    assert len(lines) == 4, p.stdout
    n = int(np.prod(cells))
    for _, reader, name, count, arrays in lines:
        # the legacy reader also shows the mesh-only grid of fields.xdmf as a second block
        assert int(count) in ((n, 2 * n) if reader == "legacy" and name == "fields.xdmf"
                              else (n,)), (reader, name, count)
        assert {"pressure", "velocity"} <= set(arrays.split(",")), (reader, name)
