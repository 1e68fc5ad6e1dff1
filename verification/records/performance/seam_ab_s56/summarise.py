"""Medians of the alternated runs in ab_*.txt (ab.sh's lines), per binary and rank count, and
each run's step over its own viscous solve (a stage the seam change does not touch), which
takes out the machine's drift between runs. Writes summary.txt."""
import pathlib
import statistics

here = pathlib.Path(__file__).parent
stages = ['step', 'bodies_extension', 'bodies_tensor', 'bodies_vof', 'body_stress',
          'bodies_patches', 'viscous_solve']
out = []
for path in sorted(here.glob('ab_*.txt')):
    runs = {}
    for line in path.read_text().splitlines():
        w = line.split()
        label, np_ = w[0], w[2]
        vals = dict(zip(w[5::2], map(float, w[6::2])))  # 'step' and each stage
        runs.setdefault(label, []).append(vals)
    out.append(f'{path.name} ({np_} rank(s)), seconds per step, median of '
               f'{len(runs["base"])} runs each:')
    out.append('| binary | ' + ' | '.join(stages) + ' | step / viscous_solve (each run) |')
    out.append('|---' * (len(stages) + 2) + '|')
    for label, rs in runs.items():
        ratios = ', '.join(f'{r["step"] / r["viscous_solve"]:.2f}' for r in rs)
        out.append(f'| {label} | ' + ' | '.join(
            f'{statistics.median(r.get(s, 0.0) for r in rs):.3f}' for s in stages)
            + f' | {ratios} |')
    base, seam = (statistics.median(r['step'] / r['viscous_solve'] for r in runs[k])
                  for k in ('base', 'seam'))
    out.append(f'median step / viscous_solve: base {base:.2f}, seam {seam:.2f} '
               f'(base over seam {base / seam:.3f})')
    out.append('')
(here / 'summary.txt').write_text('\n'.join(out) + '\n')
print('\n'.join(out))
