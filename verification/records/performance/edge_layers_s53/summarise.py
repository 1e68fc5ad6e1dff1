"""Medians of the alternated runs in ab_*.txt (ab.sh's lines), per binary and rank count."""
import pathlib
import statistics

here = pathlib.Path(__file__).parent
for path in sorted(here.glob('ab_*.txt')):
    runs = {}
    for line in path.read_text().splitlines():
        w = line.split()
        label, np_ = w[0], w[2]
        vals = dict(zip(w[5::2], map(float, w[6::2])))  # 'step' and each stage
        runs.setdefault(label, []).append(vals)
    stages = ['step', 'bodies_extension', 'bodies_tensor', 'bodies_vof', 'body_stress',
              'viscous_solve']
    print(f'{path.name} ({np_} rank(s)), seconds per step, median of {len(runs["base"])} runs each:')
    print('| binary | ' + ' | '.join(stages) + ' |')
    print('|---' * (len(stages) + 1) + '|')
    for label, rs in runs.items():
        print(f'| {label} | ' + ' | '.join(
            f'{statistics.median(r.get(s, 0.0) for r in rs):.3f}' for s in stages) + ' |')
    print()

# One rank against two (speedup_1_2_ranks.txt: labels np1_r and np2_r).
rows = [line.split() for line in (here / 'speedup_1_2_ranks.txt').read_text().splitlines()]
by_np = {}
for w in rows:
    by_np.setdefault(w[2], []).append(dict(zip(w[5::2], map(float, w[6::2]))))
stages = ['step', 'viscous_solve', 'bodies_extension', 'bodies_tensor', 'bodies_vof', 'body_stress']
print('speedup_1_2_ranks.txt, seconds per step (medians of 3 runs) and 1-rank over 2-rank time:')
print('| ranks | ' + ' | '.join(stages) + ' |')
print('|---' * (len(stages) + 1) + '|')
med = {n: {s: statistics.median(r[s] for r in rs) for s in stages} for n, rs in by_np.items()}
for n in sorted(med):
    print(f'| {n} | ' + ' | '.join(f'{med[n][s]:.3f}' for s in stages) + ' |')
print('| speedup | ' + ' | '.join(f'{med["1"][s] / med["2"][s]:.2f}' for s in stages) + ' |')
pairs = [a['step'] / b['step'] for a, b in zip(by_np['1'], by_np['2'])]
print('pair by pair: ' + ', '.join(f'{p:.2f}' for p in pairs))
