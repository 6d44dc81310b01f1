#!/usr/bin/env python3
"""The README's generated blocks: written from a run, and checked against one so that they cannot drift.

  readme_blocks.py check  AGGPACK_EXE REPO_ROOT [--only record|console]
  readme_blocks.py update AGGPACK_EXE REPO_ROOT [--only record|console]

A block lies between `<!-- generated: KIND ARGS -->` and `<!-- end generated -->`:

  record summary | record protocols   tables from docs/reproduce_of_record.json, the reproduce.json
                                      of the full `aggpack reproduce` the README quotes
  console [$ ]aggpack ARGS            what `aggpack ARGS` prints, as a ```text block (with a
                                      leading "$ aggpack ARGS" line when the marker has "$ ");
                                      run from a scratch folder, examples/ paths given absolute
                                      and written back relative, so the output is the user's

`check` regenerates every block and compares (console output with its wall times masked:
they differ from run to run); it also checks that the record is a full reproduce with the
runs `aggpack reproduce --dry-run` plans now, and that the README's other run counts of
`reproduce` modes are the planned ones. Exit 1 on a difference, saying how to regenerate.
`update` rewrites the blocks in place (scripts/update_readme.sh).
"""
import argparse
import difflib
import json
import pathlib
import re
import shlex
import subprocess
import sys
import tempfile

RECORD = "docs/reproduce_of_record.json"
BEGIN = re.compile(r"^<!-- generated: (?P<kind>\w+) (?P<args>.*?) -->$")
END = "<!-- end generated -->"
MINUS = "\u2212"
# The examples as the README names them (the record has their numbers, not these words).
EXAMPLE_LABELS = {
    "example1": ("Example 1", "Example 1: 1733 × 1 in, L = 12 in"),
    "example2": ("Example 2", "Example 2: 2000 × 0.5 in + 1000 × 1 in, L = 10 in"),
}
# Other run counts the README states, as (pattern whose group 1 is the count, reproduce's options).
RUN_COUNT_CLAIMS = [
    (r"full report took [\d.]+ min with the flag on\s+two cores \((\d+) runs", ["--whole-grading"]),
]
# Wall times in console output: "4.64 s", "1.2 min", "350 ms".
WALL_TIME = re.compile(r"\b\d+(?:\.\d+)?(?= (?:s|min|ms)\b)")


def signed(value, digits):
    return f"{value:+.{digits}f}".replace("-", MINUS)


def experiment_text(value):
    """A measured density as the paper prints it: 0.6108, 0.660."""
    text = f"{value:.4f}"
    return text[:-1] if text.endswith("0") else text


def stat(s):
    return f"{s['mean']:.4f} ± {s['sd']:.4f}"


def record_summary(record):
    seeds = record["seeds"]
    lines = [f"The summary tables of the full run of record (`{RECORD}`:",
             f"aggpack {record['aggpack_version']}, {record['runs']} runs, seeds 1–{seeds}):",
             "",
             "| case | paper after deposition | ours after deposition | paper after DEM | ours after DEM | experiment "
             "| ours − experiment |",
             "| --- | --- | --- | --- | --- | --- | --- |"]
    for key, (_, label) in EXAMPLE_LABELS.items():
        ex = record["examples"][key]
        dem, experiment = ex["after_dynamics"], ex["experiment"]
        difference = dem["mean"] - experiment
        lines.append(f"| {label} | {ex['paper']['after_deposition']:.3f} | {stat(ex['after_deposition'])} | "
                     f"{ex['paper']['after_dynamics']:.3f} | {stat(dem)} | {experiment_text(experiment)} | "
                     f"{signed(difference, 4)} ({signed(100 * difference / experiment, 1)} %) |")
    mixes = record["table2"]
    # As the report: each mix after DEM when it was settled, else after deposition.
    ours = [m["after_dynamics"]["mean"] if m["after_dynamics"]["mean"] is not None else m["after_deposition"]["mean"]
            for m in mixes]
    settled = mixes[0]["after_dynamics"]["mean"] is not None
    ours_error = sum(100 * (o - m["experiment"]) / m["experiment"] for o, m in zip(ours, mixes)) / len(mixes)
    paper_error = sum(100 * (m["paper"]["mean"] - m["experiment"]) / m["experiment"] for m in mixes) / len(mixes)
    experiments = [m["experiment"] for m in mixes]
    shipped = re.search(r"sand cut at ([\d.]+ in)", record["sensitivity"][0]["variant"])
    how = ", ".join(filter(None, [f"sand cut at {shipped.group(1)}" if shipped else "",
                                  "" if settled else "no DEM"]))
    lines += ["",
              "| case | mixes | measured density | paper's computation − experiment | ours after "
              f"{'DEM' if settled else 'deposition'} − experiment |",
              "| --- | --- | --- | --- | --- |",
              f"| Table 2: mean error against the experiments | {len(mixes)} | {min(experiments):.3f}–{max(experiments):.3f} | "
              f"{signed(paper_error, 1)} % | {signed(ours_error, 1)} %{f' ({how})' if how else ''} |"]
    return lines


def record_protocols(record):
    tapping = record["protocols"]["example1"]["tapping"]
    taps = re.match(r"(.*?) at ", tapping)
    lines = [f"| case | drop-and-roll | then DEM (the paper's method) | pour | pour, then "
             f"{taps.group(1) if taps else tapping} | experiment |",
             "| --- | --- | --- | --- | --- | --- |"]
    for key, (name, _) in EXAMPLE_LABELS.items():
        p, experiment = record["protocols"][key], record["examples"][key]["experiment"]
        cells = [f"{p[k]['mean']:.4f} ({signed(p[k]['mean'] - experiment, 3)})"
                 for k in ("drop_and_roll", "drop_and_roll_then_dem", "pour", "pour_then_tapping")]
        lines.append(f"| {name} | {' | '.join(cells)} | {experiment_text(experiment)} |")
    return lines


def console(exe, root, args):
    """What `aggpack ARGS` prints to stdout, run as a user in the checkout would see it."""
    echo = args.startswith("$ ")
    words = shlex.split(args[2:] if echo else args)
    if words[0] != "aggpack":
        raise SystemExit(f"README.md: a console block's command must start with aggpack: {args}")
    given = [str(root / w) if w.startswith("examples/") else w for w in words[1:]]
    with tempfile.TemporaryDirectory() as scratch:  # the run's out/ lands here, not in the checkout
        result = subprocess.run([exe, *given], cwd=scratch, capture_output=True, text=True, timeout=600)
    if result.returncode != 0:
        raise SystemExit(f"aggpack {' '.join(given)}: exit {result.returncode}\n{result.stderr}")
    lines = result.stdout.replace(f"{root}/", "").rstrip("\n").splitlines()
    return ["```text", *([args] if echo else []), *lines, "```"]


def blocks(text):
    """(begin line index, end line index, kind, args) of every generated block."""
    lines, found, open_at = text.splitlines(), [], None
    for k, line in enumerate(lines):
        match = BEGIN.match(line)
        if match:
            if open_at is not None:
                raise SystemExit(f"README.md:{k + 1}: a generated block opens inside the one of line {open_at[0] + 1}")
            open_at = (k, match["kind"], match["args"])
        elif line == END:
            if open_at is None:
                raise SystemExit(f"README.md:{k + 1}: {END} with no block open")
            found.append((open_at[0], k, open_at[1], open_at[2]))
            open_at = None
    if open_at is not None:
        raise SystemExit(f"README.md:{open_at[0] + 1}: generated block not closed by {END}")
    return lines, found


def planned_runs(exe, root, options):
    plan = subprocess.run([exe, "reproduce", "--dry-run", *options], cwd=root, capture_output=True, text=True,
                          timeout=60)
    match = re.search(r"^runs: (\d+) ", plan.stdout, re.M)
    if plan.returncode != 0 or not match:
        raise SystemExit(f"aggpack reproduce --dry-run {' '.join(options)}: exit {plan.returncode}\n"
                         f"{plan.stdout}{plan.stderr}")
    return int(match.group(1))


def check_run_counts(exe, root, record, text):
    """The record is a full reproduce of the current plan; the README's other counts are planned ones."""
    problems = []
    planned = planned_runs(exe, root, [])
    if record["mode"] != "full" or record["runs"] != planned:
        problems.append(f"{RECORD}: a {record['mode']} reproduce of {record['runs']} runs, but a full reproduce now "
                        f"plans {planned}: renew it with bash scripts/update_readme.sh --rerun-reproduce")
    for pattern, options in RUN_COUNT_CLAIMS:
        match = re.search(pattern, text, re.S)
        if not match:
            problems.append(f"README.md: no sentence matching {pattern!r} (the run count of reproduce "
                            f"{' '.join(options)}); update RUN_COUNT_CLAIMS in {pathlib.Path(__file__).name}")
            continue
        planned = planned_runs(exe, root, options)
        if int(match.group(1)) != planned:
            line = text.count("\n", 0, match.start(1)) + 1
            problems.append(f"README.md:{line}: says {match.group(1)} runs for reproduce {' '.join(options)}, "
                            f"which plans {planned}")
    return problems


def read_record(root):
    path = root / RECORD
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as e:
        raise SystemExit(f"{path}: {e}; it is the reproduce.json of a full `aggpack reproduce` "
                         "(scripts/update_readme.sh says how to make it)")


# The build's name (aggpack --version: the release and its commit) changes with every commit.
BUILD_NAME = re.compile(r"aggpack \d+\.\d+\.\d+(\+[0-9A-Za-z.]+)?")


def masked(lines):
    return [BUILD_NAME.sub("aggpack <version>", WALL_TIME.sub("<t>", line)) for line in lines]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("command", choices=["check", "update"])
    parser.add_argument("exe", type=lambda path: str(pathlib.Path(path).resolve()))
    parser.add_argument("root", type=pathlib.Path)
    parser.add_argument("--only", choices=["record", "console"])
    a = parser.parse_args()
    root = a.root.resolve()
    readme = root / "README.md"
    text = readme.read_text()
    lines, found = blocks(text)
    record = None if a.only == "console" else read_record(root)
    # Blank lines around a table: it ends before the end marker in every Markdown reader.
    makers = {"record": lambda args: ["", *{"summary": record_summary, "protocols": record_protocols}[args](record), ""],
              "console": lambda args: console(a.exe, root, args)}
    stale, out, last = [], [], 0
    for begin, end, kind, args in found:
        out += lines[last:begin + 1]
        last = end
        current = lines[begin + 1:end]
        if kind not in makers:
            raise SystemExit(f"README.md:{begin + 1}: unknown generated block kind {kind!r}: record or console")
        if a.only and kind != a.only:
            out += current
            continue
        fresh = makers[kind](args)
        compare = masked if kind == "console" else (lambda x: x)
        if compare(fresh) != compare(current):
            diff = "\n".join(difflib.unified_diff(current, fresh, "README.md", f"generated: {kind} {args}", lineterm=""))
            stale.append(f"README.md:{begin + 1}: the block generated by {kind} {args} differs:\n{diff}")
            # A line that differs only in its wall time keeps the README's: no churn from a loaded machine.
            kept = {masked([line])[0]: line for line in current} if kind == "console" else {}
            out += [kept.get(masked([line])[0], line) for line in fresh]
        else:
            out += current  # unchanged but for wall times: keep the README's, no churn
        print(f"README.md:{begin + 1}: {kind} {args}: {'differs' if compare(fresh) != compare(current) else 'ok'}")
    out += lines[last:]
    # A stale block is rewritten by update; a stale record or count needs a person.
    problems = check_run_counts(a.exe, root, record, text) if a.only in (None, "record") else []
    if a.command == "update":
        readme.write_text("\n".join(out) + "\n")
        print(f"rewrote {readme}" if stale else "README.md already up to date")
    else:
        problems = stale + problems
    if not found:
        problems.append("README.md: no generated blocks found")
    for p in problems:
        print(p)
    if problems and a.command == "check":
        print("To regenerate the blocks: bash scripts/update_readme.sh (after a full reproduce if the record is stale)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
