"""``pasibot analyze``: the main job. Runs every report section into an output folder.

Each section is ``pasibot_pin.report.<name>.section(out_dir) -> str`` (or ``build(out_dir)``, which
also hands back the numbers the summary quotes): it runs its studies, writes its files into
``out_dir`` and returns its Markdown. ``report.md`` opens with the answers box (the ``answers`` step,
:mod:`pasibot_pin.report.answers`: no files, its facts carry the box's lines), then a summary of
verdicts, and holds no wall-clock time. The longest sections run in pieces (:data:`PLANS`); all share one pool of
:data:`pasibot_pin.jobs.WORKERS` processes, longest first. ``report.md`` keeps the order of :data:`STEPS`.
"""

from __future__ import annotations

import argparse
import importlib
import time
from pathlib import Path

from pasibot_pin.cli.common import add_force_option, add_out_folder_option, check_output_folder
from pasibot_pin.files import MARKER, OutputFolder
from pasibot_pin.report.files import write_text_atomic

STEPS: list[tuple[str, str]] = [
    ("answers", "answers"),
    ("walking", "walking_section"),
    ("model", "model"),
    ("kinematics", "kinematics"),
    ("animation", "animation"),
    ("dynamics", "torques"),
    ("contact_energy", "contact_energy"),
    ("design_exploration", "design_exploration"),
    ("floor", "floor"),
    ("simulation", "simulation"),
]
"""(step name, report module) in report order."""

LEAD: tuple[str, ...] = ("walking",)
"""Steps whose sections come right after the Answers box, before the summary of verdicts."""

ESTIMATES: dict[str, float] = {
    "answers": 2.0,
    "walking": 8.0,
    "kinematics": 6.7,
    "contact_energy": 6.7,
    "dynamics": 2.9,
    "animation": 2.9,
    "model": 0.4,
    "design_exploration": 0.6,
}
"""CPU time [s] of the steps besides the planned ones (measured; they only order the work)."""

PRELOAD: tuple[str, ...] = (
    "matplotlib.pyplot",
    "PIL.Image",
    "PIL.PngImagePlugin",
    "PIL.GifImagePlugin",
    "PIL.ImageDraw",
    "PIL.ImageFont",
    "PIL.JpegImagePlugin",
    "PIL.BmpImagePlugin",
    "PIL.PpmImagePlugin",
    "matplotlib.backends.backend_agg",
    "xacro",
    "xacro.substitution_args",
    "xml.dom.expatbuilder",
    "zipfile",
    "numpy.polynomial",
    "pasibot_pin.viz.plots_layout",
    "umsgpack",
    "meshcat",
    "meshcat.servers.zmqserver",
    "pasibot_pin.viz.pin_meshcat",
    *(f"pasibot_pin.report.{module}" for _, module in STEPS),
)
"""Modules imported once before the pool's workers fork (:func:`pasibot_pin.jobs.run_jobs`' ``preload``):
what more than one worker imports (every section draws; both animation jobs write a meshcat page and a
GIF), about 1.6 s of CPU that each worker would otherwise spend importing them again. Pillow's plugins,
``backend_agg``, xacro's substitutions (yaml) and XML parser, the figures' layout, ``zipfile`` and
``numpy.polynomial`` were imported on first use by both workers (``PYTHONPROFILEIMPORTTIME=1``: about
0.1 s of CPU each)."""

PLANS: dict[str, str] = {"simulation": "SimulationPlan", "floor": "FloorPlan"}
"""Steps run as pool jobs: name -> class in its report module (``jobs()``, ``done(key, result)``, ``section()``)."""


def run_step(name: str, out_dir: Path):
    """Run one step: (its :class:`~pasibot_pin.report.markdown.Section`, its wall time [s] for the console)."""
    from pasibot_pin.report.markdown import Section  # deferred: keeps the CLI's start fast

    start = time.perf_counter()
    module = importlib.import_module(f"pasibot_pin.report.{dict(STEPS)[name]}")
    built = module.build(Path(out_dir)) if hasattr(module, "build") else Section(module.section(Path(out_dir)))
    return built, time.perf_counter() - start


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("analyze", help="run the full analysis into an output folder (the main job)")
    add_out_folder_option(p, Path("out"), "report.md, its figures, CSVs and animations")
    add_force_option(p, "write into an output folder that already holds files")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run every step on one pool, longest pieces first, and write ``report.md``."""
    out_dir: Path = check_output_folder(args.out, "--out")
    if out_dir.is_dir() and any(p.name != MARKER for p in out_dir.iterdir()) and not args.force:
        raise FileExistsError(f"--out {out_dir} already holds files; pass --force to write over them")
    folder = OutputFolder(out_dir).claim(force=args.force)  # marked, locked; --force only in pasibot's folders
    try:
        _run(out_dir)
    except BaseException:
        folder.discard()  # a failed or stopped run leaves nothing it created
        raise
    folder.release()
    return 0


def _run(out_dir: Path) -> None:
    """Every step into ``out_dir`` (claimed), then ``report.md``."""
    from pasibot_pin.jobs import WORKERS, Job, run_jobs  # deferred: keeps the CLI's start fast
    from pasibot_pin.report import answers  # deferred: keeps the CLI's start fast
    from pasibot_pin.report.markdown import report_text  # deferred: keeps the CLI's start fast

    built: dict = {}  # step name -> its Section
    plans = {
        name: getattr(importlib.import_module(f"pasibot_pin.report.{dict(STEPS)[name]}"), cls)(out_dir)
        for name, cls in PLANS.items()
    }
    start = time.perf_counter()

    def tagged(name: str, jobs) -> list:
        return [Job(j.estimate, (name, j.key), j.fn, j.args) for j in jobs or ()]

    def on_done(key, result):
        if key[0] == "step":
            built[key[1]], seconds = result
            print(f"[{key[1]}] done in {seconds:.1f} s", flush=True)
            return None
        return tagged(key[0], plans[key[0]].done(key[1], result))

    jobs = [Job(ESTIMATES[name], ("step", name), run_step, (name, out_dir)) for name in ESTIMATES]
    jobs += [job for name, plan in plans.items() for job in tagged(name, plan.jobs())]
    run_jobs(jobs, on_done, WORKERS, preload=PRELOAD)
    built.update({name: plan.section() for name, plan in plans.items()})
    print(f"[{'], ['.join(plans)}] and everything else done in {time.perf_counter() - start:.1f} s", flush=True)
    facts = {name: b.facts for name, b in built.items()}
    answers.complete(facts)  # the box: the answers step's lines and the walking section's (one walk for both)
    lead = [built[name].markdown for name in LEAD]
    text = report_text([built[name].markdown for name, _ in STEPS if name not in LEAD], facts, lead)
    report = write_text_atomic(out_dir / "report.md", text)
    print(f"wrote {report}")
