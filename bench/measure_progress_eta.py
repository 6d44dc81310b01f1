#!/usr/bin/env python3
"""How good is the progress line's time left for the DEM stage? Runs an aggpack command on a
pseudo-terminal (script(1) with timing), reads back every refresh of the progress line, and
prints the time left it showed against the time the stage really took from then on.

  python3 bench/measure_progress_eta.py ./build/aggpack run examples/example1.toml --out /tmp/eta --threads 1
"""
import os
import re
import shlex
import subprocess
import sys
import tempfile


def seconds(text):
    return sum(int(v) * {"h": 3600, "min": 60, "s": 1}[u] for v, u in re.findall(r"(\d+) (h|min|s)\b", text))


def main(command):
    with tempfile.TemporaryDirectory() as tmp:
        typescript, timing = os.path.join(tmp, "typescript"), os.path.join(tmp, "timing")
        env = dict(os.environ, COLUMNS="100")
        subprocess.run(["script", "-q", "-T", timing, "-c", shlex.join(command), typescript], env=env, check=True,
                       stdout=subprocess.DEVNULL)
        data = open(typescript, "rb").read()
        position = data.index(b"\n") + 1 if data.startswith(b"Script started") else 0
        clock, refreshes, stage_end = 0.0, [], None
        for line in open(timing):
            delay, count = line.split()
            clock += float(delay)
            chunk = data[position:position + int(count)].decode(errors="replace")
            position += int(count)
            for m in re.finditer(r"dynamics: (?:[a-z ,]+?, )?([0-9.]+) s simulated[^\r]*?(about|at most) ([0-9hmin s]+?) left", chunk):
                refreshes.append((clock, float(m.group(1)), m.group(2), seconds(m.group(3))))
            if refreshes and stage_end is None and "analysis" in chunk:
                stage_end = clock
    if not refreshes or stage_end is None:
        sys.exit("no DEM progress seen: is the command a run with a dynamics stage?")
    print(f"{'wall s':>7} {'simulated s':>11} {'shown':>8} {'left s':>7} {'actual s':>8} {'ratio':>6}")
    ratios = []
    for clock, simulated, kind, left in refreshes:
        actual = stage_end - clock
        if actual > 1.0:
            ratios.append(left / actual)
        print(f"{clock:7.1f} {simulated:11.3f} {kind:>8} {left:7d} {actual:8.1f} {left / max(actual, 1e-9):6.2f}")
    ratios.sort()
    print(f"{len(refreshes)} refreshes; shown / actual over those with more than 1 s left: median "
          f"{ratios[len(ratios) // 2]:.2f}, range {ratios[0]:.2f}-{ratios[-1]:.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
