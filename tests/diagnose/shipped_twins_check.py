#!/usr/bin/python3
"""Every shipped twin can run: each assets/diagnosis/*/twin_*.toml, and each twin of each shipped validation matrix
(the files scripts/twin_matrix.py --script writes for it, on its own table and, for the flowing matrix, on the
120 rpm table a GPU session runs it on), passes `wetdem twin FILE --check`: the case resolves at every condition,
the periodic slice is thicker than twice the neighbour reach there, the observables exist. Nothing is run: seconds.
A fresh matrix of the flowing drum once stopped at its first twin, whose PSD tails needed a thicker slice.
usage: shipped_twins_check.py SOURCE_DIR WETDEM"""
import glob
import os
import shutil
import subprocess
import sys
import tempfile

src, wetdem = sys.argv[1], os.path.abspath(sys.argv[2])
failures = []


def check(twin_file, what):
    r = subprocess.run([wetdem, "twin", twin_file, "--check"], cwd=src, capture_output=True, text=True)
    if r.returncode != 0 or "nothing run" not in r.stdout:
        failures.append(f"{what}: {twin_file}: exit {r.returncode}: {(r.stderr or r.stdout).strip()}")


twins = sorted(glob.glob(os.path.join(src, "assets", "diagnosis", "*", "twin_*.toml")))
for f in twins:
    check(f, "shipped twin")
matrices = sorted(f for f in glob.glob(os.path.join(src, "assets", "diagnosis", "*", "*.toml"))
                  if "[[twin]]" in open(f).read())
tmp = tempfile.mkdtemp(prefix="wetdem-shipped-twins-")
n_matrix_twins = 0
fast = os.path.join(src, "assets", "diagnosis", "flowing", "twin_null_fast.toml")
for m in matrices:
    runs = [([], "")]
    if m.endswith(os.path.join("flowing", "matrix.toml")):
        runs.append((["--twin-base", fast], "-fast"))
    for extra, tag in runs:
        name = os.path.relpath(m, src).replace(os.sep, "_")[:-5] + tag
        out = os.path.join(tmp, name)
        r = subprocess.run([sys.executable, os.path.join(src, "scripts", "twin_matrix.py"), m, "--out", out,
                            "--script", os.path.join(tmp, name + ".sh")] + extra,
                           cwd=src, capture_output=True, text=True)
        if r.returncode != 0:
            failures.append(f"{m}{tag}: twin_matrix.py --script: exit {r.returncode}: {r.stderr.strip()}")
            continue
        made = sorted(glob.glob(os.path.join(out, "*", "twin.toml")))
        if not made:
            failures.append(f"{m}{tag}: no twin files written")
        for f in made:
            check(f, f"{os.path.relpath(m, src)}{tag}")
        n_matrix_twins += len(made)
shutil.rmtree(tmp)
if len(twins) < 10 or len(matrices) < 8:
    failures.append(f"found {len(twins)} twin files and {len(matrices)} matrices under assets/diagnosis: fewer "
                    "than shipped (a moved folder?)")
if failures:
    sys.exit("FAIL:\n" + "\n".join(failures))
print(f"shipped twins: {len(twins)} twin files and {n_matrix_twins} matrix twins ({len(matrices)} matrices) check")
