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
(4) a restart continues the run exactly: the run stopped at the row nearest t = 2.5e-4 s
    (time.max_steps, a checkpoint there) and continued with --restart to 5e-4 s writes
    adhesion.csv and bodies.csv identical (text, bit for bit) to the uninterrupted run's,
    and the same adhesion totals in summary.json, on 1 and on 2 ranks (the checkpoint holds
    the receptors, bonds and counters, and every draw is keyed by receptor id and step);
    the 1-rank checkpoint continued on 2 ranks gives the 1-rank run's rows;
    a checkpoint of another seed or receptor count, one without the adhesion state, and one
    holding it for a case without [adhesion] are refused (exit 2, naming the key or the
    state) before anything is written;
(5) the run without [adhesion] writes no adhesion.csv and no adhesion entry."""
import os
import shutil

from efsi_harness import check, csv_rows, parse_args, run, run_summary

args = parse_args()
case = os.path.join(args.cases, "platelet_adhesion")


rows, summary = csv_rows, run_summary
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

# (4) a restart continues the run exactly, on 1 and on 2 ranks
full_rows = rows(on[1], "adhesion.csv")
stop = min(full_rows, key=lambda r: abs(float(r["time"]) - 2.5e-4))
stop_step = int(stop["step"])
for ranks in (1, 2):
    part = os.path.join(args.output, f"restart_np{ranks}")
    run(args, case, part, ranks=ranks,
        sets=[f"time.max_steps={stop_step}", f"output.checkpoint_every={stop_step}"])
    check(rows(part, "adhesion.csv")[-1]["step"] == str(stop_step) and
          rows(part, "adhesion.csv")[-1]["bonds"] != "0",
          f"np{ranks}: first part stopped at step {stop_step}, t = {float(stop['time']):.4e} s, "
          f"holding {rows(part, 'adhesion.csv')[-1]['bonds']} bonds")
    checkpoint = os.path.join(args.output, f"checkpoint_step{stop_step}_np{ranks}.h5")
    shutil.copyfile(os.path.join(part, "checkpoint.h5"), checkpoint)
    run(args, case, part, ranks=ranks, extra=["--restart", checkpoint])
    for name in ("adhesion.csv", "bodies.csv"):
        with open(os.path.join(on[ranks], name)) as f:
            want = f.read().splitlines()
        with open(os.path.join(part, name)) as f:
            got = f.read().splitlines()
        after = [k for k, line in enumerate(want[1:], 1) if int(line.split(",")[0]) > stop_step]
        worst = 0.0
        for a, b in zip(want[1:], got[1:]):
            for x, y in zip(a.split(","), b.split(",")):
                try:
                    x, y = float(x), float(y)
                except ValueError:
                    continue
                if x != y:
                    worst = max(worst, abs(x - y) / max(abs(x), abs(y)))
        check(got == want and len(after) > 0,
              f"np{ranks}: {name} after the restart equals the uninterrupted run's bit for bit "
              f"({len(after)} rows after step {stop_step}, {len(want) - 1} in all; largest "
              f"relative difference {worst:.1e})")
    a_full, a_part = summary(on[ranks])["adhesion"], summary(part)["adhesion"]
    check(a_full == a_part, f"np{ranks}: summary.json's adhesion entry equals the uninterrupted "
          f"run's ({a_part['bonds_formed']} formed, {a_part['bonds_broken']} broken, impulse on "
          f"the platelet {a_part['impulse_on_bodies']} N s)")

# ... and on another rank count: the 1-rank checkpoint continued on 2 ranks (the receptors and
# bonds are held alike by every rank, the fields are global arrays) writes the 1-rank run's
# rows bit for bit (all but bodies.csv's `bytes`, the body's memory, which depends on the rank
# count).
checkpoint = os.path.join(args.output, f"checkpoint_step{stop_step}_np1.h5")
cross = os.path.join(args.output, "restart_np1_on_np2")
run(args, case, cross, ranks=2, extra=["--restart", checkpoint])
for name in ("adhesion.csv", "bodies.csv"):
    want = [r for r in rows(on[1], name) if int(r["step"]) > stop_step]
    got = rows(cross, name)
    for r in want + got:
        r.pop("bytes", None)
    check(got == want, f"1-rank checkpoint continued on 2 ranks: {name}'s {len(got)} rows after "
          f"step {stop_step} equal the 1-rank run's")

# A checkpoint that does not fit the case is refused before anything is written.
for label, case_path, extra_sets, ckpt, needles in (
        ("another seed", case, ["adhesion.seed=8"], checkpoint,
         ["adhesion.seed: checkpoint '7', case '8'"]),
        ("another receptor count", case, ["adhesion.receptors[0].count=1000"], checkpoint,
         ["adhesion.receptors[0].count: checkpoint '2000', case '1000'"]),
        ("a case without [adhesion]", off_case, [], checkpoint,
         ["holds 'adhesion' state", "which this case does not have"]),
        ("a checkpoint without adhesion", case, [], os.path.join(off, "checkpoint.h5"),
         ["holds no 'adhesion' state", "[adhesion]"])):
    refused = os.path.join(args.output, "restart_refused")
    proc = run(args, case_path, refused, sets=extra_sets, extra=["--restart", ckpt], expect=2)
    check(all(n in proc.stderr for n in needles) and ckpt in proc.stderr,
          f"restart with {label} refused: {proc.stderr.strip()[:240]}")
    check(not os.path.exists(refused), f"the refused restart ({label}) wrote nothing")

# (7) receptors that move with the platelet (adhesion.receptor_motion = "rigid"): bonds form,
# 1 and 2 ranks agree (the fit's sums over the ranks round differently: to 1e-10), the cloud
# keeps its shape, momentum balances exactly with the wall's support, and the bonds, now
# stretched by the platelet's own motion, slow it more than flow-carried receptors do.
import h5py  # noqa: E402
import numpy as np  # noqa: E402

rigid = {}
for ranks in (1, 2):
    rigid[ranks] = os.path.join(args.output, f"rigid_np{ranks}")
    run(args, case, rigid[ranks], ranks=ranks, sets=['adhesion.receptor_motion="rigid"'])
r1, r2 = summary(rigid[1])["adhesion"], summary(rigid[2])["adhesion"]
check(r1["max_bonds"] > 0, f"rigid receptors bind: up to {r1['max_bonds']} bonds")
rb1 = [int(r["bonds"]) for r in rows(rigid[1], "adhesion.csv")]
rb2 = [int(r["bonds"]) for r in rows(rigid[2], "adhesion.csv")]
check(rb1 == rb2, f"rigid: bond counts identical on 1 and 2 ranks at all {len(rb1)} rows")
c1, c2 = summary(rigid[1])["bodies"][0]["centroid"], summary(rigid[2])["bodies"][0]["centroid"]
err = max(abs(a - b) / abs(a) for a, b in zip(c1, c2))
check(err <= 1e-10, f"rigid: platelet centroid on 1 and 2 ranks agrees to {err:.1e} relative")
check(all(w == -b for w, b in zip(r1["reaction_on_walls"], r1["force_on_bodies"])) and
      all(w == -b for w, b in zip(r1["impulse_on_walls"], r1["impulse_on_bodies"])),
      f"rigid: the walls' reaction (bonds and contact) is minus the force on the platelet: "
      f"impulse {r1['impulse_on_bodies']} N s")


def receptor_cloud(out):
    with h5py.File(os.path.join(out, "checkpoint.h5"), "r") as f:
        x = f["adhesion/receptor_x"][...].reshape(-1, 3)
    return np.linalg.norm(x - x.mean(axis=0), axis=1)


first = os.path.join(args.output, "rigid_first_step")
run(args, case, first, sets=['adhesion.receptor_motion="rigid"', "time.max_steps=1",
                             "output.checkpoint_every=1"])
d0, d1 = receptor_cloud(first), receptor_cloud(rigid[1])
shape_err = float(np.max(np.abs(d1 - d0)) / np.max(d0))
check(shape_err <= 1e-9, f"rigid: every receptor keeps its distance to the cloud's centre from "
      f"step 1 to the end, to {shape_err:.1e} of the radius")
v_rigid = late_velocity(rigid[1])
check(v_rigid < v_on, f"rigid receptors slow the platelet more: {v_rigid:.4e} m/s against "
      f"{v_on:.4e} m/s with flow-carried receptors and {v_off:.4e} m/s without adhesion")
