"""``pasibot find-walker``: from "a walker at this crank speed" to a design file.

Searches the design space (the sole's extents ahead of and behind joint 13 by default; any numeric
field with ``--vary NAME=LO:HI``) for designs that walk ``--steps`` steps on the floor at ``--omega``,
with Optuna's TPE sampler and the walking verdict. It prints
how many candidates walked and writes the best walker (by ``--objective``: the shortest sole, the
least energy per metre or the smallest hip pitch) to ``--out`` as a design file that
``pasibot walk --design FILE`` confirms. If none walks within ``--budget`` candidates, it says so,
writes nothing and exits 1. Needs the ``sweep`` extra (optuna).

``--3d`` walks each candidate on the 3-D floor (the hip free to roll and yaw; feet or legs that would
meet are ``collided``); without ``--design`` its base is the upright walker to build (interleaved comb
soles, ``designs/3d/``), so the sole's length is searched with feet that can stay upright.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from pasibot_pin.cli.common import add_design_option, add_force_option, check_output_file, design_of
from pasibot_pin.errors import ParameterError


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("find-walker", help="search for a walker at a crank speed; write it as a design file",
                       description=__doc__)  # fmt: skip
    p.add_argument("--omega", type=float, default=None, help="the crank speed the walker must walk at [rad/s] (needed)")
    best = "best walker: shortest sole, least energy per metre, or smallest hip pitch (default sole)"
    p.add_argument("--objective", default="sole", metavar="sole|energy|pitch", help=best)
    p.add_argument("--budget", type=int, default=40, help="candidates to walk, 1 to 10000 (default 40)")
    p.add_argument("--steps", type=int, default=20, help="steps each candidate must walk (default 20)")
    vary = "a varied field and its range (repeatable; default parallel_toe=3:10, parallel_heel=3:10)"
    p.add_argument("--vary", action="append", default=None, metavar="NAME=LO:HI", help=vary)
    workers = "worker processes (default 2; the search asks 4 candidates ahead, so more than 4 add nothing)"
    p.add_argument("--workers", type=int, default=None, help=workers)
    seed = "the sampler's seed (default 0): the same seed gives the same candidates and file on any --workers"
    p.add_argument("--seed", type=int, default=0, help=seed)
    p.add_argument("--out", type=Path, required=True, metavar="FILE.toml", help="the design file to write")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    spatial = "walk each candidate in 3-D (the hip free to roll; default base: the comb-soled walker of designs/3d/)"
    p.add_argument("--3d", dest="spatial", action="store_true", help=spatial)
    add_design_option(p)
    add_force_option(p, "overwrite --out")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Check every input before any work, search, print the count and write the best walker."""
    from pasibot_pin.explore.find_walker import (  # deferred: keeps the CLI's start fast
        DEFAULT_RANGES,
        WalkerSearch,
        find_walker,
    )
    from pasibot_pin.explore.plan import parse_range  # deferred: keeps the CLI's start fast
    from pasibot_pin.extras import require  # deferred: keeps the CLI's start fast
    from pasibot_pin.jobs import WORKERS  # deferred: keeps the CLI's start fast
    from pasibot_pin.model.design import Design  # deferred: keeps the CLI's start fast
    from pasibot_pin.studies.walking import (  # deferred: keeps the CLI's start fast
        SEARCH_BUDGET,
        check_walk_budget,
        walk_cost,
    )
    from pasibot_pin.studies.walking_map3d import recommended_walker  # deferred: keeps the CLI's start fast

    if args.omega is None:
        raise ParameterError("--omega is needed: the crank speed the walker must walk at [rad/s]")
    require("sweep", ["optuna"], "pasibot find-walker")
    if args.out.suffix not in (".toml", ".json"):
        raise ParameterError(f"--out must name a .toml or .json design file, got {str(args.out)!r}")
    out = check_output_file(args.out, "--out", args.force)
    base = design_of(args) or (recommended_walker() if args.spatial else Design(variant="parallel"))
    ranges = tuple(parse_range(t) for t in args.vary) if args.vary else DEFAULT_RANGES
    search = WalkerSearch(args.omega, args.objective, args.budget, args.steps, ranges, base, args.seed, args.spatial)
    what = f"--budget {args.budget} walks of --steps {args.steps} at --omega {args.omega:g} rad/s"
    cost = walk_cost(args.omega, args.steps, walks=args.budget, spatial=args.spatial)
    check_walk_budget(cost, what + (" in 3-D" if args.spatial else ""), SEARCH_BUDGET)
    workers = args.workers if args.workers is not None else WORKERS
    result = find_walker(search, workers=workers, progress=not args.no_progress)
    walkers = result.walkers
    where = " in 3-D" if args.spatial else ""
    print(f"{len(walkers)} of {len(result.candidates)} candidates walk {args.steps} steps{where} at "
          f"{args.omega:g} rad/s ({result.wall_s:.0f} s)", flush=True)  # fmt: skip
    best = result.best()
    if best is None:
        print(f"no walker found in {len(result.candidates)} candidates: nothing written (try --budget, --vary)")
        return 1
    values = ", ".join(f"{k} = {v:.3g}" for k, v in walkers[0].values.items())
    print(f"best by {args.objective}: {values} (score {walkers[0].score:.4g})", flush=True)
    assert out is not None
    out.parent.mkdir(parents=True, exist_ok=True)  # checked creatable up front; made only when a walker is written
    best.save(out, force=args.force)
    print(f"wrote {out}; check it with: pasibot walk --design {out}" + (" --3d" if args.spatial else ""))
    return 0
