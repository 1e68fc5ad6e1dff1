#!/usr/bin/python3
"""Relaxation of a sheared capsule (docs/method.md, "The membrane's stiffness, measured by
relaxation"): the effective stiffness of the discrete membrane, without tank-treading.

    /usr/bin/python3 verification/records/capsule_longtime/relaxation.py OUT N[:BOX[:W]] ... > relaxation.json
    /usr/bin/python3 verification/records/capsule_longtime/relaxation.py --table  (docs/method.md)

N cells per diameter (then, comma-separated, extra case keys for both runs, key=value as
for --set: "16,body[0].strain_model=\"tensor\"" or "16,time.cfl=0.25"; "ca=0.025" sets the
capillary number instead of 0.0125, and a Skalak law with "body[0].law=\"skalak\"" and
"body[0].area_dilation=C" takes the small-deformation D = 5/4 (2 + 3C)/(1 + 2C) x 1.5 Ca
of capsule_shear.py in place of 25/4 Ca); BOX the box in radii (8, the cases' box, unless given: 16 doubles it,
with its walls at +-8 moving at +-8 while sheared); W the smoothing width in cells (the
case's 0.75 unless given).

For each N (cells per diameter): cases/capsule_shear at Ca 0.0125 (small deformation), Re
1e-4 (fluid.density = 1e-4, so the flow follows the walls within ~1e-3), sheared to t = 0.6
(D near its steady 25/4 Ca); then the walls stand still (the walls' `stop_time` key) and the
capsule relaxes for 0.6 more, in the same run. The fit: D(t) of the phi = 1/2 body (bodies.csv taylor_deformation_sharp) over the
window 0.6 D0 >= D >= 0.15 D0, log-linear, gives the relaxation time tau.

Small-deformation theory for a neo-Hookean capsule with equal viscosities: a sphere starts
deforming at dD/dt = E (E = shear rate / 2; the runs show 0.49-0.50 at t -> 0) and settles at
D = 25/4 Ca (Barthes-Biesel & Rallison 1981), so a single-mode relaxation has
tau = 2 x 25/4 Ca / shear rate = 12.5 Ca (= 0.156 here). tau / 12.5 Ca > 1 means the discrete
membrane is that much softer than the continuous one (the walls at 4 a also slow the
relaxation by a few per cent: not removed here). Output: JSON on stdout.
"""
import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(REPO / "verification" / "studies"))
from membrane_relaxation import CA, T_SHEAR, run_sets  # noqa: E402
from membrane_relaxation import fit as study_fit  # noqa: E402
from capsule_shear import skalak_linear_theory  # noqa: E402

EFSI = REPO / "build" / "bin" / "efsi"


def run(out: Path, n: int, box=8, width=None, extra=(), ca=CA):
    """Sheared to T_SHEAR, then the walls stand still (boundary.*.stop_time) to the end:
    the study's run (verification/studies/membrane_relaxation.py) with extra keys."""
    sets = run_sets(n, ca=ca, box=float(box))
    if width is not None:
        sets["body[0].smoothing_width"] = repr(width)
    cmd = [str(EFSI), "run", str(REPO / "cases" / "capsule_shear"), "-o", str(out)]
    for k, v in sets.items():
        cmd += ["--set", f"{k}={v}"]
    for kv in extra:
        cmd += ["--set", kv]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def steady_small_deformation(ca: float, extra) -> float:
    if any(kv.replace(" ", "") == 'body[0].law="skalak"' for kv in extra):
        c = float(next(kv.split("=", 1)[1] for kv in extra if kv.startswith("body[0].area_dilation=")))
        return skalak_linear_theory(ca, c)
    return 25.0 / 4.0 * ca


def fit(relax: Path, t0: float, ca: float = CA, extra=()) -> dict:
    f = study_fit(relax, t0, 2 * steady_small_deformation(ca, extra))
    return {"Ca": ca, **{k: v for k, v in f.items() if k not in ("t", "D")}}


def table():
    """docs/method.md's table from relaxation.json (beside this script)."""
    d = json.loads((Path(__file__).parent / "relaxation.json").read_text())
    print("| run | box [a] | smoothing width [cells] | other keys | D0 | tau | theory | tau / theory "
          "| D / D0 at the end |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, m in d["runs"].items():
        box = name.split("_box")[1].split("_")[0] if "_box" in name else "8"
        w = name.split("_w")[1].split("_")[0] if "_w" in name else "0.75"
        keys = ", ".join(p for p in name.split("_", 1)[-1:] if "=" in p) or "-"
        print(f"| {name} | {box} | {w} | {keys} | {m['D0']:.4f} | {m['tau']:.4f} | "
              f"{m.get('tau_theory', 12.5 * CA):.4f} | "
              f"{m['tau_over_theory']:.3f} | "
              + (f"{m['residual_fraction']:.3f} |" if "residual_fraction" in m else "- |"))


def main():
    if sys.argv[1:] == ["--table"]:
        table()
        return
    root, out = Path(sys.argv[1]), {}
    for spec in sys.argv[2:]:
        spec, *extra = spec.split(",")
        ca = float(next((kv[3:] for kv in extra if kv.startswith("ca=")), CA))
        extra = [kv for kv in extra if not kv.startswith("ca=")]
        parts = spec.split(":")
        n, box = int(parts[0]), int(parts[1]) if len(parts) > 1 else 8
        width = float(parts[2]) if len(parts) > 2 else None
        name = f"d{n}" + (f"_box{box}" if box != 8 else "") + (f"_w{width:g}" if width else "")
        name += (f"_ca{ca:g}" if ca != CA else "") + "".join(
            "_" + kv.split("=")[0].split(".")[-1] + "=" + kv.split("=", 1)[1].replace('"', "")
            for kv in extra)
        d = root / name
        run(d / "run", n, box=box, width=width, extra=extra, ca=ca)
        out[name] = fit(d / "run", T_SHEAR, ca, extra)
    json.dump({"Ca": CA, "shear_until": T_SHEAR, "runs": out}, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
