#!/usr/bin/env python3
"""Make, on a twin, the measurements a diagnosis asks for next, and write the observation table with them added.

A diagnosis's report ends, when the data leave it undecided, with the measurements to make next
(docs/diagnosis.md; report.md's "Measurements to make next", diagnosis.json's `measure_next`): the one that
separates two tied effects, the one that would close an open strength interval, and where a candidate the table
cannot see would show, each with how often to make it. In a laboratory the engineer makes them, as the table's
rows were made. On a twin the truth can be asked: this script runs `wetdem twin` on the twin's own file at the
proposed conditions (its truth, seeds and instrument noise, drawn from a noise seed of its own; the report's sigma
only for an observable the twin has no noise for) and appends those rows to the table. A measurement made k times
runs k times the truth's seeds (new ones) with the noise over sqrt(k); its row's n counts those runs. Diagnosing the new
table again closes the loop:

    scripts/twin_measure.py TWIN.toml OBS.csv DIAGNOSIS_DIR --out OBS2.csv --store STORE [--noise-seed N]
    build/host/wetdem diagnose D.toml --observations OBS2.csv --out DIAG2 --store STORE

A drum speed or a run length the table never varied becomes a new column, with the model's own value (from
`wetdem check`) in the rows measured so far: the same resolved case, so the same runs in the store. A proposal
with any other key the table lacks is not measured, and neither is a measurement the table already has. Exit status 0 with the new table written when something was
measured; 3 when the diagnosis asks for nothing that can be measured here (nothing is written); 1 on an error.
scripts/twin_matrix.py --measure-next N runs this loop on every twin of a matrix.
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

def asked_for(diagnosis, path="diagnosis.json"):
    """The measurements the report asks for, as (condition, observable, sigma, repeats), in the report's order:
    diagnosis.json's "measure_next", which wetdem writes from the rules its paragraph states (report.h,
    AskedMeasurement). A diagnosis.json from before that list is an error: run the diagnosis again (its runs are in
    the store)."""
    if "measure_next" not in diagnosis:
        sys.exit(f"{path}: no \"measure_next\" list (written by an older wetdem): run the diagnosis again; its runs "
                 "are in the store")
    return [(m["condition"], m["observable"], m["sigma"], max(1, int(m["repeats"]))) for m in diagnosis["measure_next"]]


def parse_condition(text):
    """'liquid.content=2.5 %, drum.rpm=60' -> {'liquid.content': '2.5 %', 'drum.rpm': '60'}"""
    out = {}
    for part in text.split(", "):
        k, _, v = part.partition("=")
        out[k.strip()] = v.strip()
    return out


def drop_sections(text, names):
    """The TOML text without the tables whose header is one of `names` ('[noise]', '[[points]]', ...)."""
    out, skip = [], False
    for line in text.splitlines(keepends=True):
        head = line.strip()
        if head.startswith("["):
            skip = head.split("#")[0].strip() in names
        if not skip:
            out.append(line)
    return "".join(out)


# Condition keys a next experiment may propose beyond the table's columns (a drum speed, a longer run): the model's
# own value, from `wetdem check` (SI, its [section] name), as the table would write it.
MODEL_VALUE = {
    "drum.rpm": ("drum", "rotation_rad_per_s", lambda w: f"{w * 60.0 / (2.0 * math.pi):.6g}"),
    "run.duration": ("run", "duration_s", lambda s: f"{s:.6g} s"),
}


def model_values(wetdem, case):
    """The model's value of each MODEL_VALUE key: `wetdem check CASE` prints the case resolved, in SI."""
    r = subprocess.run([wetdem, "check", case], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"wetdem check {case} failed:\n{r.stdout}{r.stderr}")
    section, found = "", {}
    for line in r.stdout.splitlines():
        line = line.split("#")[0].strip()
        if line.startswith("[") and line.endswith("]"):
            section = line[1:-1]
        elif "=" in line:
            k, _, v = line.partition("=")
            for key, (sec, name, fmt) in MODEL_VALUE.items():
                if section == sec and k.strip() == name:
                    found[key] = fmt(float(v))
    return found


def toml_value(v):
    """A condition's value as the twin file would hold it: a number as a number, else a string."""
    try:
        float(v)
        return v
    except ValueError:
        return json.dumps(v)


def twin_noise(text):
    """The twin file's [noise] table ({observable: sd}), read without a TOML library (a lent machine may lack one)."""
    out, inside = {}, False
    for line in text.splitlines():
        head = line.split("#")[0].strip()
        if head.startswith("["):
            inside = head == "[noise]"
            continue
        m = re.match(r'^"?([A-Za-z0-9_.]+)"?\s*=\s*([-+0-9.eE]+)\s*$', head) if inside else None
        if m:
            out[m.group(1)] = float(m.group(2))
    return out


def twin_seeds(text):
    """The twin file's truth seeds (seeds = [..])."""
    m = re.search(r"^seeds\s*=\s*\[([^\]]*)\]", text, flags=re.M)
    return [int(x) for x in m.group(1).replace(",", " ").split()] if m else []


def twin_for(twin_text, points, noise, noise_seed):
    """The twin file at these points (each a dict of condition keys) with these noises, its truth and seeds kept."""
    text = drop_sections(twin_text, {"[conditions]", "[[points]]", "[noise]"})
    if re.search(r"^noise_seed\s*=", text, flags=re.M):
        text = re.sub(r"^noise_seed\s*=.*$", f"noise_seed = {noise_seed}", text, flags=re.M)
    else:
        text = f"noise_seed = {noise_seed}\n" + text
    text += "".join("\n[[points]]\n" + "".join(f"{json.dumps(k)} = {toml_value(v)}\n" for k, v in p.items())
                    for p in points)
    text += "\n[noise]\n" + "".join(f"{k} = {v!r}\n" for k, v in noise.items())
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("twin", help="the twin file the table was made from (its truth is what gets measured)")
    ap.add_argument("observations", help="the observation table the diagnosis read")
    ap.add_argument("diagnosis", help="the diagnosis's output folder (its diagnosis.json)")
    ap.add_argument("--out", required=True, help="the table with the new rows")
    ap.add_argument("--store", required=True, help="run store (the twin's runs at the table's conditions are there)")
    ap.add_argument("--wetdem", default="build/host/wetdem")
    ap.add_argument("--noise-seed", type=int, default=900, help="noise seed of the new measurements")
    ap.add_argument("--record", metavar="FILE",
                    help="also record what was measured in FILE (JSON: one entry per output table, replaced when "
                         "the same table is written again)")
    ap.add_argument("--jobs", type=int, default=None,
                    help="runs at a time (default: wetdem's, one per core on lavapipe, 1 on a GPU)")
    ap.add_argument("--batch", type=int)
    a = ap.parse_args()

    path = os.path.join(a.diagnosis, "diagnosis.json")
    diagnosis = json.load(open(path))
    asked = asked_for(diagnosis, path)
    if not asked:
        print("nothing to measure: the report asks for no measurement")
        return 3
    with open(a.observations, newline="") as f:
        rows = list(csv.DictReader(f))
        header = list(rows[0].keys()) if rows else []
    keys = [h for h in header if h not in ("observable", "value", "sigma", "n", "note")]
    if not rows or not keys:
        sys.exit(f"{a.observations}: no rows or no condition columns")

    def same_condition(row, cond):
        return all(row.get(k, "").strip() == cond.get(k, "") for k in keys)

    twin_dir = os.path.dirname(os.path.abspath(a.twin))
    twin_text = open(a.twin).read()
    m = re.search(r'^case\s*=\s*"([^"]+)"', twin_text, flags=re.M)
    case = os.path.join(twin_dir, m.group(1)) if m else None
    todo, skipped, known = [], [], None

    for condition, observable, sigma, repeats in asked:
        cond = parse_condition(condition)
        missing = sorted(set(cond) - set(keys))
        if missing and case and not set(missing) - set(MODEL_VALUE):
            # A drum speed or a run length the table never varied: a new column, the model's own value in every
            # row measured so far (the same resolved case, so the same runs in the store).
            known = known or model_values(a.wetdem, case)
            if set(missing) <= set(known):
                at = header.index("observable")
                for k in missing:
                    header.insert(at, k)
                    keys.append(k)
                    for r in rows:
                        r[k] = known[k]
                    print(f"new column {k}: the rows so far at the model's {known[k]}")
                missing = []
        if missing:
            skipped.append(f"{observable} at {condition} (the table has no column {missing})")
            continue
        # Keys of the table the proposal does not name keep the value of the table's first row that matches the
        # named ones (the base of the proposal), else the first row's.
        base = next((r for r in rows if all(r[k].strip() == v for k, v in cond.items())), rows[0])
        full = {k: cond.get(k, base[k].strip()) for k in keys}
        if any(same_condition(r, full) and r["observable"] == observable for r in rows):
            if repeats == 1:
                skipped.append(f"{observable} at {condition} (already in the table)")
                continue
            # Asked to be made again, k times: the k new measurements' mean takes the row's place.
            rows = [r for r in rows if not (same_condition(r, full) and r["observable"] == observable)]
            print(f"replaced: {observable} at {condition}, to be made {repeats} times")
        todo.append((full, observable, sigma, repeats))
    # A column a later measurement added: the earlier ones are at the model's own value there, as the table's rows
    # (a twin needs the same condition keys at every point).
    todo = [({k: full[k] if k in full else known[k] for k in keys}, o, sg, rep) for full, o, sg, rep in todo]
    for s in skipped:
        print(f"not measured: {s}")
    if not todo:
        print("nothing to measure: the diagnosis asks for no measurement this table can take")
        return 3

    if any(k > 1 for *_, k in todo) and "n" not in header:
        header.insert(header.index("note") if "note" in header else len(header), "n")
        for r in rows:
            r["n"] = ""
    # As the table's rows were made: the twin's own instrument noise (its [noise]; the report's sigma for an
    # observable it has none of, an assay), and the twin's truth seeds. A measurement made k times is k
    # measurements of k drums: k times the truth's seeds (new ones, after the twin's) and the instrument's noise
    # over sqrt(k), so that the bed's own spread shrinks with the repeats as a laboratory's would.
    instrument = twin_noise(twin_text)
    seeds = twin_seeds(twin_text)
    if not seeds:
        sys.exit(f"{a.twin}: no seeds = [...] list")
    # The case path relative to the twin file, as wetdem reads it.
    text = re.sub(r'^case\s*=\s*"([^"]+)"', lambda m: f'case = "{os.path.join(twin_dir, m.group(1))}"', twin_text,
                  flags=re.M)
    measured = {}
    for k in sorted({rep for *_, rep in todo}):
        group = [t for t in todo if t[3] == k]
        points = []
        for full, _, _, _ in group:
            if full not in points:
                points.append(full)
        for r in rows:  # a point of the table (a twin needs two conditions)
            if len(points) >= 2:
                break
            p = {key: r[key].strip() for key in keys}
            if p not in points:
                points.append(p)
        noise = {}
        for _, observable, sigma, _ in group:
            noise[observable] = instrument.get(observable, sigma) / math.sqrt(k)
        more = [max(seeds) + 1 + j for j in range(len(seeds) * (k - 1))]
        work = tempfile.mkdtemp(prefix="twin_measure_")
        tf = os.path.join(work, "twin.toml")
        body = re.sub(r"^seeds\s*=.*$", f"seeds = {seeds + more}", text, count=1, flags=re.M)
        open(tf, "w").write(twin_for(body, points, noise, a.noise_seed + k - 1))
        cmd = ([a.wetdem, "twin", tf, "--out", os.path.join(work, "twin"), "--store", a.store, "--quiet"]
               + (["--jobs", str(a.jobs)] if a.jobs else []) + (["--batch", str(a.batch)] if a.batch else []))
        r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if r.returncode != 0:
            sys.exit(f"wetdem twin failed ({r.returncode}; its files: {work}):\n{r.stdout}")
        with open(os.path.join(work, "twin", "observations.csv"), newline="") as f:
            measured[k] = list(csv.DictReader(f))
        shutil.rmtree(work)  # the runs stay in the store; the twin's table is read
    added, what = [], []
    for full, observable, _, repeats in todo:
        row = next((m for m in measured[repeats] if m["observable"] == observable and same_condition(m, full)),
                   None)
        if row is None:
            sys.exit(f"wetdem twin gave no {observable} at {full}")
        row = {h: row.get(h, "") for h in header}
        row["note"] = "measured next"  # n: the truth runs behind it, as the twin counts them (k x its seeds)
        added.append(row)
        what.append(f"{observable} at {', '.join(f'{k}={v}' for k, v in full.items())}"
                    + (f" ({repeats} times)" if repeats > 1 else ""))
        print(f"measured: {what[-1]} = {row['value']} (sigma {row['sigma']})")
    # The table as wetdem writes it: condition values quoted, the rest as they are.
    with open(a.out, "w") as f:
        f.write(",".join(header) + "\n")
        for row in rows + added:
            f.write(",".join(json.dumps(row[h]) if h in keys else str(row[h]) for h in header) + "\n")
    if a.record:
        entries = json.load(open(a.record)) if os.path.exists(a.record) else []
        entries = [e for e in entries if e["table"] != os.path.basename(a.out)]
        entries.append({"table": os.path.basename(a.out), "measured": what})
        with open(a.record, "w") as f:
            json.dump(entries, f, indent=1)
    print(f"table: {a.out} ({len(rows)} rows + {len(added)} measured)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
