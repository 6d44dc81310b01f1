#!/usr/bin/env python3
"""A LAMMPS dump measured in virtual boxes, beside aggpack's own bed of the same scenario.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/lammps_dump_compare.py --out out/py_lammps --threads 2
    PYTHONPATH=build/python /usr/bin/python3 examples/python/lammps_dump_compare.py --dump my_run.dump --cube 0.03

With --dump, reads that dump (its last snapshot; --timestep for another) and measures it in
virtual cubes placed as aggpack places them (docs/method.md section 2). Without, makes one: a
small bed (300 spheres of 1 cm) is deposited and settled twice from the same start, once by
aggpack's DEM and once by LAMMPS (dynamics.engine = "lammps", which needs Debian's `lammps`),
and LAMMPS's dump is measured beside aggpack's bed.
"""
import argparse
import pathlib

import numpy as np

import aggpack

SMALL_BED = {
    "title": "a small bed, settled by aggpack and by LAMMPS", "seed": 5,
    "container": {"side": 0.06, "height": 0.3},
    "particles": {"diameter": 0.01, "count": 300},
    "material": {"youngs_modulus": 1e8, "wall_youngs_modulus": 1e8},
    "deposition": {},
    "dynamics": {"max_time": 1.0},
    "analysis": {"box_sides": [0.03]},
}


def describe(name, analysis):
    d = analysis["density"]
    print(f"{name}: {analysis['particle_count']} spheres, density {d['mean']:.4f} "
          f"(sd {d['sd']:.4f} over {len(d['boxes'])} cubes), coordination {analysis['coordination']['mean']:.2f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dump", type=pathlib.Path, help="a LAMMPS dump (x y z and radius or diameter columns)")
    parser.add_argument("--timestep", type=int, help="the dump's snapshot (default: the last)")
    parser.add_argument("--cube", type=float, action="append", help="virtual cube side, m (repeatable)")
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out/py_lammps"))
    parser.add_argument("--threads", type=int, default=0, help="aggpack's OpenMP threads (0: all cores)")
    args = parser.parse_args()
    cubes = args.cube or [0.03]

    if args.dump:
        dump = aggpack.read_bed(args.dump, timestep=args.timestep)
        describe(f"{args.dump} ({dump.format})", aggpack.analyze(dump, cubes=cubes, soft_contacts=True))
        return

    scenario = aggpack.Scenario.from_dict(SMALL_BED)
    ours = aggpack.run(scenario, out=args.out / "aggpack", overwrite=True, threads=args.threads)
    theirs = aggpack.run(scenario.with_overrides(['dynamics.engine="lammps"']), out=args.out / "lammps",
                         overwrite=True, threads=args.threads)
    dumps = sorted((args.out / "lammps" / "lammps").glob("**/*.dump"))
    dump = aggpack.read_bed(dumps[-1])
    print(f"LAMMPS's dump: {dumps[-1]} ({dump.format})")
    ours_analysis = aggpack.analyze(ours.bed, cubes=cubes)
    dump_analysis = aggpack.analyze(dump, cubes=cubes, soft_contacts=True)
    describe("aggpack's DEM", ours_analysis)
    describe("LAMMPS's dump", dump_analysis)
    # The dump is the bed LAMMPS's run of aggpack handed back: the same spheres, the same places.
    assert np.allclose(np.sort(dump.radii), np.sort(theirs.bed.radii), rtol=1e-12)
    difference = dump_analysis["density"]["mean"] - ours_analysis["density"]["mean"]
    print(f"LAMMPS - aggpack: {difference:+.4f} (docs/validation.md: within 0.003 on this bed)")


if __name__ == "__main__":
    main()
