#!/usr/bin/env bash
# Grains of several spheres against the literature (issue 38, docs/validation.md "Grains of
# several spheres"):
#  1. frictionless elongated grains, aspect ratio L/I = 1 (spheres) to 3 (prolate: I = S,
#     rounded family, 7 spheres each), poured and settled: Donev et al. 2004 (Science 303, 990)
#     and Man et al. 2005 (PRL 94, 198001) find the jammed density of smooth spheroids rising
#     from the sphere's 0.64 to a maximum of about 0.735 near aspect 1.5 and falling beyond;
#  2. frictional (mu 0.5) poured grains: spheres, and angular grains near a cube (elongation 1,
#     flatness 1, 8 corners, 8 spheres), which Baker and Kudrolli 2010 (PRE 82, 061304) find
#     looser than spheres (dice 0.50-0.54 poured against spheres' 0.58-0.60).
# Each: 400 particles of I = 8 mm (700 of the angular grains, which are smaller for their I) in
# a 6 cm periodic box, E = 1e7 Pa, poured in 6 batches at 0.25 (of the grains' bounding
# spheres: one batch of the longest grains would fall from metres), at most 3 s simulated,
# seed 1; the density is the vertical profile's mean between one d_max
# above the floor and one below the surface (the whole footprint each slice). Two runs side
# by side, one core each (about 2 minutes each). Writes OUT_DIR/results.md (one row per run)
# and OUT_DIR/results.svg (the frictionless curve, the literature's marks beside it), and
# exits 1 when the frictionless curve does not rise above the spheres' to a maximum at an
# aspect ratio from 1.25 to 2 and fall by aspect 3, or when the angular grains do not pack
# looser than the spheres with friction. Usage:
#   bash scripts/validate_grains_literature.sh [OUT_DIR]   (default out/validate_grains_literature)
set -euo pipefail
cd "$(dirname "$0")/.."
exe=$PWD/build/aggpack
out=${1:-out/validate_grains_literature}
mkdir -p "$out"
export OMP_NUM_THREADS=1
[ -x "$exe" ] || { echo "validate_grains_literature.sh: no $exe; build first (bash scripts/build.sh)" >&2; exit 2; }

# name, particles.shape (empty: spheres), friction, count
runs=(
  "spheres_frictionless||0|400"
  "aspect_1.25|{ family = \"rounded\", spheres = 7, templates = 1, elongation = 0.8, flatness = 1, spread = 0 }|0|400"
  "aspect_1.5|{ family = \"rounded\", spheres = 7, templates = 1, elongation = 0.6666666666666666, flatness = 1, spread = 0 }|0|400"
  "aspect_2|{ family = \"rounded\", spheres = 7, templates = 1, elongation = 0.5, flatness = 1, spread = 0 }|0|400"
  "aspect_2.5|{ family = \"rounded\", spheres = 7, templates = 1, elongation = 0.4, flatness = 1, spread = 0 }|0|400"
  "aspect_3|{ family = \"rounded\", spheres = 7, templates = 1, elongation = 0.3333333333333333, flatness = 1, spread = 0 }|0|400"
  "spheres_friction_0.5||0.5|400"
  "angular_cube_friction_0.5|{ family = \"angular\", spheres = 8, corners = 8, templates = 4, elongation = 1, flatness = 1, spread = 0 }|0.5|700"
)
for run in "${runs[@]}"; do
  IFS='|' read -r name shape friction count <<<"$run"
  {
    printf 'title = "grains against the literature: %s"\nseed = 1\n' "$name"
    printf '[container]\nside = 0.06\nheight = 0.5\nsides = "periodic"\n'
    printf '[particles]\ndiameter = 0.008\ncount = %s\n' "$count"
    [ -n "$shape" ] && printf 'shape = %s\n' "$shape"
    printf '[material]\nyoungs_modulus = 1e7\nwall_youngs_modulus = 1e7\nfriction_particle = %s\nfriction_wall = %s\n' \
      "$friction" "$friction"
    printf '[pour]\nbatches = 6\nsolid_fraction = 0.25\n[dynamics]\nmax_time = 3.0\n[analysis]\nbox_sides = [0.01]\n'
  } > "$out/$name.toml"
done
printf '%s\n' "${runs[@]}" | cut -d'|' -f1 |
  xargs -P 2 -I{} "$exe" run "$out/{}.toml" --quiet --threads 1 --no-checkpoint --overwrite --out "$out/{}"

python3 - "$out" "${runs[@]}" <<'PY'
import json, sys
out, runs = sys.argv[1], [r.split("|")[0] for r in sys.argv[2:]]
def interior(name):
    s = json.load(open(f"{out}/{name}/summary.json"))
    bed, v = s["bed"], s["profiles"]["vertical"]
    lo, hi = bed["floor_m"] + bed["d_max_m"], bed["surface_m"] - bed["d_max_m"]
    slices = [f for z, f in zip(v["z_m"], v["solid_fraction"]) if lo <= z <= hi]
    d = s["stages"]["dynamics"]
    return sum(slices) / len(slices), len(slices), d["ended_by"], d["simulated_time_s"], s["wall_clock_s"]["total"]
rows, density = [], {}
for name in runs:
    phi, n, ended, t, wall = interior(name)
    density[name] = phi
    rows.append(f"| {name} | {phi:.4f} | {n} | {ended} at {t:.2f} s | {wall:.0f} s |")
with open(f"{out}/results.md", "w") as f:
    f.write("| run | interior density | slices | ended | wall clock |\n| --- | --- | --- | --- | --- |\n")
    f.write("\n".join(rows) + "\n")
print(open(f"{out}/results.md").read())
curve = [("1", density["spheres_frictionless"])] + [(a, density[f"aspect_{a}"]) for a in ("1.25", "1.5", "2", "2.5", "3")]
# The curve as a picture, the literature's marks beside it: results.svg.
W, H, L, B = 480, 320, 60, 40  # size, left and bottom margins (px)
x = lambda a: L + (float(a) - 1.0) / 2.0 * (W - L - 20)
y = lambda phi: H - B - (phi - 0.60) / 0.15 * (H - B - 20)
svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="11">',
       f'<rect width="{W}" height="{H}" fill="white"/>',
       f'<line x1="{L}" y1="{H - B}" x2="{W - 20}" y2="{H - B}" stroke="black"/>',
       f'<line x1="{L}" y1="{H - B}" x2="{L}" y2="20" stroke="black"/>']
for a in ("1", "1.5", "2", "2.5", "3"):
    svg.append(f'<text x="{x(a):.1f}" y="{H - B + 14}" text-anchor="middle">{a}</text>')
for phi in (0.60, 0.65, 0.70, 0.75):
    svg.append(f'<text x="{L - 6}" y="{y(phi) + 4:.1f}" text-anchor="end">{phi:.2f}</text>')
svg.append(f'<text x="{(L + W) / 2}" y="{H - 8}" text-anchor="middle">aspect ratio L/I (prolate, I = S)</text>')
svg.append(f'<text x="14" y="{H / 2}" transform="rotate(-90 14 {H / 2})" text-anchor="middle">density, frictionless</text>')
points = " ".join(f"{x(a):.1f},{y(phi):.1f}" for a, phi in curve)
svg.append(f'<polyline points="{points}" fill="none" stroke="#1f77b4" stroke-width="2"/>')
svg += [f'<circle cx="{x(a):.1f}" cy="{y(phi):.1f}" r="3" fill="#1f77b4"/>' for a, phi in curve]
# Literature: spheres at 0.64; the spheroids' maximum 0.70-0.71 near aspect 1.5; ellipsoids' 0.735.
svg.append(f'<rect x="{x("1") - 4:.1f}" y="{y(0.64) - 4:.1f}" width="8" height="8" fill="none" stroke="#d62728"/>')
svg.append(f'<line x1="{x("1.5"):.1f}" y1="{y(0.71):.1f}" x2="{x("1.5"):.1f}" y2="{y(0.70):.1f}" stroke="#d62728" stroke-width="6"/>')
svg.append(f'<line x1="{x("1.25"):.1f}" y1="{y(0.735):.1f}" x2="{x("1.75"):.1f}" y2="{y(0.735):.1f}" stroke="#d62728" stroke-dasharray="4 3"/>')
svg.append(f'<text x="{W - 24}" y="34" text-anchor="end" fill="#1f77b4">aggpack, poured (7 spheres a grain)</text>')
svg.append(f'<text x="{W - 24}" y="50" text-anchor="end" fill="#d62728">jammed: spheres 0.64, spheroids 0.70-0.71,</text>')
svg.append(f'<text x="{W - 24}" y="64" text-anchor="end" fill="#d62728">ellipsoids 0.735 (dashed); Donev 2004, Man 2005</text>')
svg.append("</svg>")
open(f"{out}/results.svg", "w").write("\n".join(svg) + "\n")
best = max(curve, key=lambda c: c[1])
checks = {
    "the frictionless maximum lies above the spheres' density": best[1] > curve[0][1],
    "the frictionless maximum lies at an aspect ratio from 1.25 to 2": best[0] in ("1.25", "1.5", "2"),
    "the frictionless density falls from its maximum by aspect 3": curve[-1][1] < best[1],
    "angular grains pack looser than spheres with friction": density["angular_cube_friction_0.5"] < density["spheres_friction_0.5"],
}
for what, ok in checks.items():
    print(("ok: " if ok else "FAILED: ") + what)
sys.exit(0 if all(checks.values()) else 1)
PY
