"""aggpack: random packings of polydisperse spheres and grains, and the packing density of aggregates.

The library behind the `aggpack` command, from Python (README, "Python"):

    import aggpack
    scenario = aggpack.Scenario.from_file("examples/example2.toml", seed=3)
    report = aggpack.run(scenario, threads=2)
    report.density            # the final bed's mean virtual-box density
    report.bed.positions      # N x 3 numpy view, m
    report.summary()          # summary.json's dict
    aggpack.write_outputs(report, "out/example2")

Bad input raises aggpack.InputError (a ValueError) with the CLI's message.
"""
from ._aggpack import (  # noqa: F401
    NO_GRAIN,
    Bed,
    InputError,
    Report,
    Scenario,
    __version__,
    analyze,
    calibrate,
    export_lammps,
    grading,
    import_lammps,
    predict,
    read_bed,
    resume,
    run,
    specimen,
    toml_text,
    write_outputs,
)

__all__ = ["Bed", "InputError", "NO_GRAIN", "Report", "Scenario", "analyze", "calibrate", "export_lammps", "grading", "import_lammps",
           "predict", "read_bed", "resume", "run", "specimen", "toml_text", "write_outputs"]
