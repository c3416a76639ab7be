"""``pasibot torques``: crank and ankle torques of a seed scenario, and the fitted ankle spring.

Also holds the ``dynamics`` step of ``pasibot analyze`` (:func:`analyze_step`): every
scenario with the default model and with the ``seed`` preset, plots, CSVs, and a K_e table
whose differences are attributed to the seed's modelling choices one at a time.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from pasibot_pin.cli.common import write_columns_csv


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    from pasibot_pin.model.scenarios import ACCELERATION_MODES, PRESETS, SCENARIOS, SWING_FOOT_MODES

    p = sub.add_parser("torques", help="crank/ankle torques of a seed scenario and the fitted ankle spring K_e")
    p.add_argument("--scenario", default="run1", help=f"one of {', '.join(SCENARIOS)} (default run1)")
    p.add_argument("--preset", default="default", help=f"modelling preset: {', '.join(PRESETS)} (default default)")
    p.add_argument("--omega", type=float, default=None, help="override the crank speed [rad/s] (0 = quasi-static)")
    p.add_argument("--samples", type=int, default=61, help="samples over one stance (default 61; not with a window)")
    p.add_argument("--steps", type=int, default=1, help="half crank turns (steps) to run, stance swapping (default 1)")
    p.add_argument("--swing-foot", choices=SWING_FOOT_MODES, default=None, help="override: level or square")
    p.add_argument("--accelerations", choices=ACCELERATION_MODES, default=None, help="override the acceleration mode")
    p.add_argument("--inertia", choices=("point", "uniform"), default=None, help="override: point masses or rods")
    p.add_argument("--no-swap", action="store_true", help="undo the seed's L5/L6 mass swap")
    p.add_argument("--csv", type=Path, default=None, help="write the samples to this CSV file")
    p.add_argument("--plot", type=Path, default=None, help="write torques vs beta with the fit to this image")
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.set_defaults(func=run)


def write_result_csv(path: Path, result) -> None:
    """Write a :class:`~pasibot_pin.dynamics.inverse.TorqueResult` as CSV (SI units, full precision)."""
    write_columns_csv(path, result.columns())


def _choices(args: argparse.Namespace):
    from pasibot_pin.model.scenarios import get_preset

    choices = get_preset(args.preset)
    changes = {}
    if args.swing_foot is not None:
        changes["swing_foot"] = args.swing_foot
    if args.accelerations is not None:
        changes["accelerations"] = args.accelerations
    if args.inertia is not None:
        changes["inertia"] = args.inertia
    if args.no_swap:
        changes["swap_l5_l6"] = False
    return choices.with_(**changes) if changes else choices


def compute(args: argparse.Namespace):
    """Run the scenario of ``args``; return (scenario, choices, result, fit)."""
    from pasibot_pin.dynamics.inverse import STANCE_RANGE, crank_grid, run_scenario
    from pasibot_pin.model.scenarios import get_scenario
    from pasibot_pin.studies.spring_fit import fit_result

    scenario = get_scenario(args.scenario)
    choices = _choices(args)
    if args.steps < 1:
        raise ValueError(f"parameter '--steps' must be >= 1, got {args.steps}")
    thetas = None
    if choices.fit_thetas is None or args.steps > 1:
        per_step = max(int(args.samples), 2)
        thetas = crank_grid(STANCE_RANGE[0], STANCE_RANGE[0] + math.pi * args.steps, (per_step - 1) * args.steps + 1)
    result = run_scenario(scenario, choices, thetas=thetas, omega=args.omega)
    window = choices.fit_thetas if thetas is None else None
    fit = fit_result(result, window, warn=False)
    return scenario, choices, result, fit


def run(args: argparse.Namespace) -> int:
    """Print K_e and write the optional CSV and plot."""
    for path, option in ((args.csv, "--csv"), (args.plot, "--plot")):
        if path is not None and path.exists() and not args.force:
            raise FileExistsError(f"{option} {path} exists; pass --force to overwrite it")
    scenario, choices, result, fit = compute(args)
    print(f"scenario {scenario.name}: {scenario.description}; preset {args.preset}; {len(result)} samples")
    print(f"K_e = {fit.K_e:.2f} N.m/rad")
    print(fit.summary())
    if scenario.seed_K_e is not None:
        print(
            f"seed stored K_e = {scenario.seed_K_e:.2f} N.m/rad (without swap and lag: {scenario.seed_K_e_clean:.2f})"
        )
    if args.csv is not None:
        write_result_csv(args.csv, result)
        print(f"wrote {args.csv}")
    if args.plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        from pasibot_pin.viz.plots_dynamics import plot_torques_vs_beta

        fig = plot_torques_vs_beta(result, fit, title=f"{scenario.description} [{args.preset}]")
        args.plot.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")
    return 0


# --------------------------------------------------------------------------- analyze step
def _attribution(scenario, first: float, last: float):
    """K_e as the seed's choices are switched on one at a time, from the default model to the seed preset.

    ``first`` and ``last`` are the K_e of the default model and of the seed preset (already computed).
    """
    from pasibot_pin.dynamics.inverse import run_scenario
    from pasibot_pin.model.scenarios import PRESETS, SEED_CHOICE_NAMES
    from pasibot_pin.studies.spring_fit import fit_result

    seed = PRESETS["seed"]
    choices = PRESETS["default"]
    rows = [("default model", first, 0.0)]
    previous = first
    names = list(SEED_CHOICE_NAMES.items())
    for k, (field_name, label) in enumerate(names):
        choices = choices.with_(**{field_name: getattr(seed, field_name)})
        if k == len(names) - 1:
            k_e = last
        else:
            k_e = fit_result(run_scenario(scenario, choices, reactions=False), choices.fit_thetas, warn=False).K_e
        rows.append((label, k_e, k_e - previous))
        previous = k_e
    return rows


def analyze_step(out_dir: Path, args: argparse.Namespace) -> str:
    """Every scenario with the default model and the seed preset: plots, CSV, K_e table, attribution."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from pasibot_pin.dynamics.inverse import STANCE_RANGE, crank_grid, run_scenario
    from pasibot_pin.model.scenarios import PRESETS, SCENARIOS
    from pasibot_pin.studies.spring_fit import fit_result
    from pasibot_pin.viz.plots_dynamics import plot_stiffness_table, plot_torques_vs_beta, plot_torques_vs_time

    start = time.perf_counter()
    sub = out_dir / "dynamics"
    sub.mkdir(parents=True, exist_ok=True)
    lines = [
        "## Torques and the ankle spring (constrained RNEA)",
        "",
        "Stance foot welded flat, hip level, cranks at constant omega pi apart; torques are generalised forces "
        "of theta, beta, theta', beta' (beta = angle from the forward foot to the shank). "
        "`default`: exact masses, swing foot level, exact accelerations, fit over the whole stance "
        "theta in [90, 270] deg. `seed`: every choice of the seed's MATLAB code (DESIGN §5).",
        "",
        "| scenario | omega [rad/s] | body [kg] | K_e default [N.m/rad] | R^2 | beta0 [deg] | K_e seed preset | "
        "seed stored | seed without swap/lag |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    table: dict[str, list] = {"default": [], "seed preset": [], "seed stored": []}
    warnings_text = []
    grid, axes = plt.subplots(len(SCENARIOS), 2, figsize=(13, 4 * len(SCENARIOS)))
    results = {}
    for row, (name, scenario) in enumerate(SCENARIOS.items()):
        fits = {}
        for col, preset in enumerate(("default", "seed")):
            choices = PRESETS[preset]
            result = run_scenario(scenario, choices)
            fit = fit_result(result, choices.fit_thetas, warn=False)
            fits[preset] = fit
            results[(name, preset)] = (result, fit)
            write_result_csv(sub / f"torques_{name}_{preset}.csv", result)
            plot_torques_vs_beta(result, fit, ax=axes[row, col], title=f"{scenario.description} [{preset}]")
            if fit.warning:
                warnings_text.append(f"- {name} [{preset}]: {fit.warning}")
        d, s = fits["default"], fits["seed"]
        stored = "-" if scenario.seed_K_e is None else f"{scenario.seed_K_e:.2f}"
        clean = "-" if scenario.seed_K_e_clean is None else f"{scenario.seed_K_e_clean:.2f}"
        lines.append(
            f"| {name} | {scenario.omega:g} | {scenario.body_mass:g} | {d.K_e:.2f} | {d.r2:.3f} | "
            f"{math.degrees(d.beta0):.1f} | {s.K_e:.2f} | {stored} | {clean} |"
        )
        table["default"].append(d.K_e)
        table["seed preset"].append(s.K_e)
        table["seed stored"].append(scenario.seed_K_e)
    grid.tight_layout()
    grid.savefig(sub / "torques_vs_beta.png", dpi=70)
    plt.close(grid)
    fig = plot_stiffness_table(list(SCENARIOS), table, title="ankle stiffness per scenario")
    fig.savefig(sub / "stiffness.png", dpi=100)
    plt.close(fig)
    qs_clean = fit_result(
        run_scenario(SCENARIOS["quasi-static"], PRESETS["seed-clean"], reactions=False), None, warn=False
    )
    lines += [
        "",
        "The seed's quasi-static script does not swap the L5/L6 masses (its dynamic script does): its model is the "
        f"`seed-clean` preset here, K_e = {qs_clean.K_e:.2f} N.m/rad at omega = 0 (the seed's text: about 330).",
        "",
        "![K_e per scenario](dynamics/stiffness.png)",
        "",
    ]
    if warnings_text:
        lines += ["Fit warnings:", *warnings_text, ""]

    # Attribution: switch the seed's choices on one at a time (cumulative), per dynamic scenario.
    lines += [
        "### Where the seed's K_e comes from",
        "",
        "Each row switches one more of the seed's choices on (cumulative, top to bottom); the last row is the "
        "`seed` preset. Delta = the change that choice makes [N.m/rad].",
        "",
    ]
    names = [n for n in SCENARIOS if n != "quasi-static"]
    attribution = {
        n: _attribution(SCENARIOS[n], results[(n, "default")][1].K_e, results[(n, "seed")][1].K_e) for n in names
    }
    header = "| choice | " + " | ".join(f"{n} K_e | {n} delta" for n in names) + " |"
    lines += [header, "|---|" + "---|---|" * len(names)]
    for k, (label, _, _) in enumerate(attribution[names[0]]):
        cells = " | ".join(f"{attribution[n][k][1]:.2f} | {attribution[n][k][2]:+.2f}" for n in names)
        lines.append(f"| {label} | {cells} |")
    lines.append("")

    # Several steps at the seed's fastest speed: torques against time, stance swapping every half turn.
    scenario = SCENARIOS["run4"]
    thetas = crank_grid(STANCE_RANGE[0], STANCE_RANGE[0] + 4 * math.pi, 4 * 48 + 1)
    walk = run_scenario(scenario, PRESETS["default"], thetas=thetas)
    write_result_csv(sub / "torques_run4_two_turns.csv", walk)
    slow = run_scenario(SCENARIOS["run2"], PRESETS["default"], thetas=thetas[::4])
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(10, 8))
    plot_torques_vs_time(walk, ax=ax1, title="run4 (5 rad/s, 20 kg), default model, two crank turns")
    plot_torques_vs_time(slow, ax=ax2, title="run2 (0.1 rad/s, 16 kg), default model, two crank turns")
    fig.tight_layout()
    fig.savefig(sub / "torques_vs_time.png", dpi=80)
    plt.close(fig)
    peak = float(np.max(np.abs(walk.Ta)))
    lines += [
        "![torques vs beta, default model (left) and seed preset (right)](dynamics/torques_vs_beta.png)",
        "![torques vs time over four steps](dynamics/torques_vs_time.png)",
        "",
        f"Two crank turns of run4 (four steps, {len(walk)} samples): peak |T_a| = {peak:.2f} N.m, "
        f"peak |T_e| = {float(np.max(np.abs(walk.Te))):.1f} N.m. CSVs: `dynamics/torques_<scenario>_<preset>.csv` "
        "(columns t, theta, beta, Ta, Te, Ta_swing, Te_swing, then reactions).",
        f"(step time {time.perf_counter() - start:.1f} s)",
    ]
    return "\n".join(lines)
