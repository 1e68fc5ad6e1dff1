"""Platelet adhesion in the time step (cases/platelet_adhesion): a neo-Hookean sphere in
shear flow 30 nm above a vWF patch, its GPIb-alpha receptors binding by kinetic Monte Carlo.
(1) bonds form (adhesion.csv, summary.json);
(2) 1 and 2 ranks give the same run for the same seed: bond counts at every row equal,
    the platelet's centroid equal to 1e-12 relative;
(3) the bonds slow the platelet: its mean velocity over the last quarter of the run is
    below 0.95 of the same run without [adhesion] (measured 0.934 with the wall taking the
    bonds' reaction, 0.906 before, when -F went into the fluid at the ligand);
(6) the wall takes the reaction: summary.json's reaction_on_walls and impulse_on_walls are
    exactly minus force_on_bodies and impulse_on_bodies, and the platelet feels a net pull
    (nonzero impulse);
(4) --restart of a case with [adhesion] is refused (exit 2, naming [adhesion]) before
    anything is written;
(5) the run without [adhesion] writes no adhesion.csv and no adhesion entry."""
import csv
import json
import os

from efsi_harness import check, parse_args, run

args = parse_args()
case = os.path.join(args.cases, "platelet_adhesion")


def rows(out, name):
    with open(os.path.join(out, name)) as f:
        return list(csv.DictReader(f))


def summary(out):
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def late_velocity(out):
    """Mean x velocity of the platelet's centroid over the last quarter of the run [m/s]."""
    b = rows(out, "bodies.csv")
    t = [float(r["time"]) for r in b]
    x = [float(r["centroid_x"]) for r in b]
    a = next(k for k in range(len(t)) if t[k] >= 0.75 * t[-1])
    return (x[-1] - x[a]) / (t[-1] - t[a])


on = {}
for ranks in (1, 2):
    on[ranks] = os.path.join(args.output, f"adhesion_np{ranks}")
    run(args, case, on[ranks], ranks=ranks)

# (1) bonds form
adh = rows(on[1], "adhesion.csv")
bonds = [int(r["bonds"]) for r in adh]
s1 = summary(on[1])
check(max(bonds) > 0, f"bonds form: up to {max(bonds)} bonds, {s1['adhesion']['bonds_formed']} "
      f"formed, {s1['adhesion']['bonds_broken']} broken, first at t = "
      f"{s1['adhesion']['first_bond_time']} s")
check(sum(int(r["formed"]) for r in adh) == s1["adhesion"]["bonds_formed"],
      "adhesion.csv's formed column sums to summary.json's bonds_formed")
check(s1["adhesion"]["max_bonds"] == max(bonds) and s1["adhesion"]["bonds"] == bonds[-1],
      "summary.json's bond counts match adhesion.csv")
check("adhesion" in s1["time_step_limits"] and s1["time_step_limits"]["adhesion"] > 0,
      f"named time-step limit 'adhesion' = {s1['time_step_limits'].get('adhesion')} s")

# (2) 1 and 2 ranks
s2 = summary(on[2])
bonds2 = [int(r["bonds"]) for r in rows(on[2], "adhesion.csv")]
check(bonds == bonds2, f"bond counts identical on 1 and 2 ranks at all {len(bonds)} rows")
for key in ("bonds_formed", "bonds_broken", "max_bonds"):
    check(s1["adhesion"][key] == s2["adhesion"][key],
          f"{key} {s1['adhesion'][key]} on 1 and 2 ranks")
c1, c2 = s1["bodies"][0]["centroid"], s2["bodies"][0]["centroid"]
err = max(abs(a - b) / abs(a) for a, b in zip(c1, c2))
check(err <= 1e-12, f"platelet centroid on 1 and 2 ranks agrees to {err:.1e} relative")

# (3) the bonds slow the platelet
with open(os.path.join(case, "case.toml")) as f:
    text = f.read()
off_case = os.path.join(args.output, "no_adhesion.toml")
with open(off_case, "w") as f:
    f.write(text[:text.index("[adhesion]")] + text[text.index("[output]"):])
off = os.path.join(args.output, "no_adhesion")
run(args, off_case, off)
v_on, v_off = late_velocity(on[1]), late_velocity(off)
check(v_off > 0, f"without adhesion the platelet moves downstream at {v_off:.4e} m/s")
check(v_on < 0.95 * v_off,
      f"bonds slow it: {v_on:.4e} m/s with adhesion, {v_off:.4e} without (ratio "
      f"{v_on / v_off:.3f} < 0.95)")

# (6) the wall takes the reaction, equal and opposite
a1 = s1["adhesion"]
check(all(w == -b for w, b in zip(a1["reaction_on_walls"], a1["force_on_bodies"])) and
      all(w == -b for w, b in zip(a1["impulse_on_walls"], a1["impulse_on_bodies"])) and
      a1["impulse_on_held"] == [0.0, 0.0, 0.0],
      f"the wall's reaction is minus the bonds' force on the platelet: impulse on the platelet "
      f"{a1['impulse_on_bodies']} N s, on the wall {a1['impulse_on_walls']} N s")
check(any(b != 0 for b in a1["impulse_on_bodies"]), "the bonds put a net impulse on the platelet")
last = rows(on[1], "adhesion.csv")[-1]
check(all(float(last[f"reaction_walls_{c}"]) == -float(last[f"force_bodies_{c}"]) for c in "xyz"),
      "adhesion.csv: reaction_walls = -force_bodies on the last row")

# (5) nothing of adhesion without [adhesion]
check(not os.path.exists(os.path.join(off, "adhesion.csv")) and "adhesion" not in summary(off),
      "without [adhesion]: no adhesion.csv, no adhesion entry in summary.json")

# (4) restart refused
refused = os.path.join(args.output, "restart_refused")
proc = run(args, case, refused, extra=["--restart", os.path.join(on[1], "checkpoint.h5")],
           expect=2)
check("[adhesion]" in proc.stderr and "not checkpointed" in proc.stderr,
      f"restart refused: {proc.stderr.strip()[:160]}")
check(not os.path.exists(refused), "the refused restart wrote nothing")
