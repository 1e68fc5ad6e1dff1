"""The repository stands alone: nothing it runs reads a path outside the clone."""
import re
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]

# Absolute paths of the development machine, or the sibling folder of reading material.
OUTSIDE = re.compile(r"""(/work/|\.\./shared|["']shared["']\s*/|parent\s*/\s*["']shared["'])""")


def tracked(*patterns):
    out = subprocess.run(["git", "ls-files", *patterns], cwd=REPO, capture_output=True,
                         text=True, check=False)
    if out.returncode != 0:  # not a git checkout (an exported tree): walk it instead
        return [p.relative_to(REPO) for pat in patterns for p in REPO.rglob(pat.lstrip("*"))]
    return [Path(p) for p in out.stdout.split()]


def test_no_code_reads_outside_the_repository():
    code = tracked("*.py", "*.cpp", "*.hpp", "*.sh", "*.txt", "*.toml", "Makefile", ".ci/*")
    assert code, "no tracked files found"
    offenders = []
    for rel in code:
        text = (REPO / rel).read_text(errors="replace")
        for n, line in enumerate(text.splitlines(), 1):
            if OUTSIDE.search(line) and "test_standalone" not in str(rel):
                offenders.append(f"{rel}:{n}: {line.strip()}")
    assert offenders == [], "paths outside the repository:\n" + "\n".join(offenders)


def test_published_reference_curves_are_in_the_repository():
    data = REPO / "verification" / "data"
    assert (data / "README.md").is_file()
    for ca in (0.0125, 0.025, 0.05, 0.1, 0.2):
        assert (data / "capsule_shear" / f"pozrikidis1995_ca{ca:g}.csv").is_file()
    for law in ("neo_hookean", "skalak"):
        assert (data / "uniaxial_stretch" / f"barthes_biesel2002_{law}.csv").is_file()
    # every file in the folder is named in its README with its source
    readme = (data / "README.md").read_text()
    for sub in ("capsule_shear", "uniaxial_stretch"):
        assert f"{sub}/" in readme
