#!/usr/bin/env python3
"""Golden records: small seeded scenarios whose results guard refactoring.

  golden.py check  AGGPACK_EXE REPO_ROOT   run every tests/golden/scenarios/*.toml and compare
                                           with tests/golden/<name>.json; exit 1 on a difference
  golden.py record AGGPACK_EXE REPO_ROOT   (re)write the records: do it only on purpose, in a
                                           commit of its own, so that the change is a diff

A record holds every number and string of the run's summary.json (flattened to key paths)
except what depends on timing, the machine or where the checkout lies, and the particles:
their count, a SHA-256 of particles.csv, the mean and spread of x, y, z and r, and every
k-th particle in full. Numbers are compared within the record's own tolerance; the hash is
reported but not required, so that a last-bit change within the tolerance passes and says so.
"""
import csv
import hashlib
import json
import math
import pathlib
import statistics
import subprocess
import sys
import tempfile

# Keys that measure the machine or name the build, not the physics.
EXCLUDED = ("aggpack_version", "wall_clock_s", "particles_per_second", "particle_steps_per_second", "threads",
            "memory_bytes_per_particle", "scenario_file", "working_directory", "scenario.output.")
TOLERANCE = {
    "relative": 1e-9,
    "absolute": 1e-12,
    "why": "the same machine kind and compiler give the same bytes; the slack is for last-bit changes "
           "of libm. A new DEM kernel or summation order moves DEM numbers by far more: regenerate the "
           "records on purpose (scripts/update_golden.sh) and review the diff.",
}
SAMPLES = 16


def flatten(value, prefix, out, root):
    if isinstance(value, dict):
        for k, v in value.items():
            flatten(v, f"{prefix}.{k}" if prefix else k, out, root)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            flatten(v, f"{prefix}[{i}]", out, root)
    else:
        if any(e in prefix for e in EXCLUDED):
            return
        if isinstance(value, str):
            value = value.replace(str(root), "<repo>")
        out[prefix] = value


def particles_digest(path):
    data = path.read_bytes()
    rows = list(csv.DictReader(data.decode().splitlines()))
    columns = {c: [float(r[c]) for r in rows] for c in ("x", "y", "z", "r")}
    step = max(1, len(rows) // SAMPLES)
    return {
        "count": len(rows),
        "sha256": hashlib.sha256(data).hexdigest(),
        "mean": {c: statistics.fmean(v) for c, v in columns.items()},
        "sd": {c: statistics.pstdev(v) for c, v in columns.items()},
        "samples": [[int(rows[i]["id"])] + [columns[c][i] for c in ("x", "y", "z", "r")]
                    for i in range(0, len(rows), step)],
    }


def run(exe, scenario, out):
    subprocess.run([exe, "run", str(scenario), "--out", str(out), "--threads", "1", "--quiet"], check=True)
    summary = json.loads((out / "summary.json").read_text())
    return summary


def observe(exe, root, scenario, tmp):
    out = pathlib.Path(tmp) / scenario.stem
    summary = run(exe, scenario, out)
    flat = {}
    flatten(summary, "", flat, root)
    return {"summary": flat, "particles": particles_digest(out / "particles.csv")}


def close(a, b, tol):
    if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, (int, float)) or not isinstance(b, (int, float)):
        return a == b
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return abs(a - b) <= tol["absolute"] + tol["relative"] * max(abs(a), abs(b))


def compare(name, record, seen):
    tol = record["tolerance"]
    problems = []
    keys = sorted(k for k in set(record["summary"]) | set(seen["summary"]) if not any(e in k for e in EXCLUDED))
    for k in keys:
        if k not in seen["summary"]:
            problems.append(f"{name}: summary.{k}: in the record ({record['summary'][k]!r}), missing now")
        elif k not in record["summary"]:
            problems.append(f"{name}: summary.{k}: new ({seen['summary'][k]!r}), not in the record")
        elif not close(record["summary"][k], seen["summary"][k], tol):
            problems.append(f"{name}: summary.{k}: record {record['summary'][k]!r}, now {seen['summary'][k]!r}")
    rp, sp = record["particles"], seen["particles"]
    if rp["count"] != sp["count"]:
        problems.append(f"{name}: particles: record {rp['count']}, now {sp['count']}")
    else:
        for part in ("mean", "sd"):
            for c in rp[part]:
                if not close(rp[part][c], sp[part][c], tol):
                    problems.append(f"{name}: particles {part} {c}: record {rp[part][c]!r}, now {sp[part][c]!r}")
        for a, b in zip(rp["samples"], sp["samples"]):
            if a[0] != b[0] or not all(close(x, y, tol) for x, y in zip(a[1:], b[1:])):
                problems.append(f"{name}: particle {a[0]}: record {a[1:]}, now {b[1:]}")
    return problems


def main(mode, exe, root):
    root = pathlib.Path(root).resolve()
    folder = root / "tests" / "golden"
    scenarios = sorted((folder / "scenarios").glob("*.toml"))
    if not scenarios:
        sys.exit("no golden scenarios found")
    problems = []
    with tempfile.TemporaryDirectory() as tmp:
        for scenario in scenarios:
            seen = observe(exe, root, scenario, tmp)
            record_file = folder / f"{scenario.stem}.json"
            if mode == "record":
                record = {"scenario": f"scenarios/{scenario.name}", "tolerance": TOLERANCE, **seen}
                record_file.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")
                print(f"recorded {record_file.relative_to(root)}")
                continue
            if not record_file.exists():
                problems.append(f"{scenario.stem}: no record (run scripts/update_golden.sh on purpose)")
                continue
            record = json.loads(record_file.read_text())
            found = compare(scenario.stem, record, seen)
            problems += found
            same_bytes = record["particles"]["sha256"] == seen["particles"]["sha256"]
            print(f"{scenario.stem}: {'differs' if found else 'matches'} "
                  f"({len(record['summary'])} summary values; particles.csv "
                  f"{'the same bytes' if same_bytes else 'not the same bytes, but within the tolerance'})")
    for p in problems[:200]:
        print(p)
    if mode == "check":
        print(f"{len(scenarios) - len({p.split(':')[0] for p in problems})} passed, "
              f"{len({p.split(':')[0] for p in problems})} failed")
    return 1 if problems else 0


if __name__ == "__main__":
    if len(sys.argv) != 4 or sys.argv[1] not in ("check", "record"):
        sys.exit(__doc__)
    sys.exit(main(*sys.argv[1:]))
