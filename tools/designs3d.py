"""``make designs-3d``: ``designs/3d/``, the walkers that stay upright in 3-D, from the 3-D walking map.

Two picks from ``docs/results/walking_map3d.csv``, among the cells where our engine and the MuJoCo
twin both say ``walks``:

- the fastest crank speed, with the smallest comb reach that walks there;
- the smallest comb reach, at the fastest speed it walks at.

Each is written as a design file, walked 20 steps on our 3-D floor (and in the twin, when MuJoCo
is installed), drawn in perspective, and listed in ``designs/3d/README.md``. ``--check`` walks the
committed files again and compares them with the README's table.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from pasibot_pin.files import write_text_atomic
from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.model.spatial import free_flyer_model
from pasibot_pin.studies.walking import WalkSettings, walk_design_3d
from pasibot_pin.studies.walking_map import twin_walker
from pasibot_pin.studies.walking_map3d import Map3DCell, load_map3d, map3d_design
from pasibot_pin.viz.plots_robot3d import save_walk_3d_figure

ROOT = Path(__file__).resolve().parents[1]
MAP = ROOT / "docs" / "results" / "walking_map3d.csv"
FOLDER = ROOT / "designs" / "3d"
STEPS = 20


def candidates(cells: list[Map3DCell]) -> list[tuple[str, str, list[Map3DCell]]]:
    """(name prefix, why, cells in the order tried) of the two picks (see the module docstring).

    Both start from the map's cells where both engines walk its steps; each is then walked
    :data:`STEPS` steps in both, and the first on which both still walk is kept.
    """
    both = [c for c in cells if c.feet == "comb" and c.walks and c.twin_outcome == "walks"]
    return [
        ("upright_fastest", "the fastest crank speed that walks upright in both engines, with its smallest comb reach",
         sorted(both, key=lambda c: (-c.omega, c.value))),
        ("upright_smallest_reach", "the smallest comb reach that walks upright in both engines, at its fastest speed",
         sorted(both, key=lambda c: (c.value, -c.omega))),
    ]  # fmt: skip


def walk_both(path: Path, draw: bool = True) -> dict:
    """Our 3-D walk and the twin's of the design file ``path``, as a table row (``draw``: its picture too)."""
    design = load_design(path)
    robot = design_robot(design, 2, visuals=False)
    ours = walk_design_3d(design, WalkSettings(steps=STEPS), robot)
    row = {
        "outcome": ours.verdict.outcome,
        "steps": ours.verdict.steps,
        "advance_m": round(ours.verdict.advance_m, 3),
        "max_hip_roll_deg": round(ours.result.max_hip_roll_deg, 3),
        "min_sole_clearance_mm": round(1e3 * ours.result.min_sole_clearance_m, 1),
        "leg_clearance_mm": round(1e3 * ours.result.leg_clearance_m, 1),
    }
    twin = twin_walker()
    if twin is not None:
        m = twin(design, WalkSettings(steps=STEPS), spatial=True)
        row.update(twin_outcome=m.verdict.outcome, twin_steps=m.verdict.steps)
        row.update(twin_advance_m=round(m.verdict.advance_m, 3), twin_max_hip_roll_deg=round(m.max_hip_roll_deg, 3))
    if draw:
        _draw(path, design, robot, ours)
    return row


PICTURE_STEPS = 4
"""Steps of the walk a picture shows the end of [-]."""


def draw(path: Path) -> Path:
    """The picture of the design file ``path``: the last steps of a :data:`PICTURE_STEPS`-step 3-D walk."""
    design = load_design(path)
    robot = design_robot(design, 2, visuals=False)
    return _draw(path, design, robot, walk_design_3d(design, WalkSettings(steps=PICTURE_STEPS), robot))


def _draw(path: Path, design, robot, walk) -> Path:
    roll = walk.result.max_hip_roll_deg
    title = f"{path.stem}: {walk.verdict.short()} ({walk.verdict.steps} steps), max roll {roll:.2f} deg"
    return save_walk_3d_figure(free_flyer_model(robot.model), walk.result.q, design.footprint(),
                               path.with_suffix(".png"), title=title)  # fmt: skip


def readme(rows: list[tuple[str, str, Map3DCell, dict]], tried: list[tuple[Map3DCell, dict]]) -> str:
    """``designs/3d/README.md``: what the files are, the table, the cells tried and left out, the pictures."""
    lines = [
        "# Walkers that stay upright in 3-D",
        "",
        "Every walker in [`designs/`](../README.md) tips over sideways at its first single support when its hip is",
        "free to roll (`pasibot walk --3d`, [docs/floor3d.md](../../docs/floor3d.md)). These do not: the same",
        "linkage with interleaved comb soles, each reaching past the midline under the other leg, the two",
        "feet's prongs 1 cm apart. Picked from the 3-D walking map (`docs/results/walking_map3d.csv`,",
        "`make walking-map-3d`) by `make designs-3d` (`tools/designs3d.py`): each was walked again",
        f"{STEPS} steps on our 3-D floor and in the MuJoCo twin (`export-mjcf --3d`), and kept only where both",
        "walk every step, within 5 % of each other's advance.",
        "",
        "<!-- generated by tools/designs3d.py -->",
        "| design | omega [rad/s] | prong past the midline [L] | outcome | steps | advance [m] | max hip roll [deg] "
        "| soles apart [mm] | legs apart [mm] | twin outcome | twin steps | twin advance [m] | twin max roll [deg] |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name, _why, cell, r in rows:
        lines.append(f"| [{name}]({name}.toml) | {_cells(cell, r)} |")
    lines.append("")
    lines += [f"* **{name}**: {why}." for name, why, _c, _r in rows]
    if tried:
        lines += ["", f"Walked {STEPS} steps and left out (the twin disagrees; the 3-D map walks only 6 steps):", "",
                  "| omega [rad/s] | prong past the midline [L] | outcome | steps | advance [m] | max hip roll [deg] "
                  "| soles apart [mm] | legs apart [mm] | twin outcome | twin steps | twin advance [m] "
                  "| twin max roll [deg] |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]  # fmt: skip
        lines += [f"| {_cells(cell, r)} |" for cell, r in tried]
    lines.append("")
    lines += [f"![{name}: the walk in perspective, lengths in m]({name}.png)\n" for name, *_ in rows]
    lines.append(f"<!-- rows: {json.dumps({name: r for name, _w, _c, r in rows}, sort_keys=True)} -->")
    return "\n".join(lines) + "\n"


def _cells(cell: Map3DCell, r: dict) -> str:
    twin = [str(r.get(k, "-")) for k in ("twin_outcome", "twin_steps", "twin_advance_m", "twin_max_hip_roll_deg")]
    return (
        f"{cell.omega:g} | {cell.value:g} | {r['outcome']} | {r['steps']} | {r['advance_m']} | {r['max_hip_roll_deg']} "
        f"| {r['min_sole_clearance_mm']} | {r['leg_clearance_mm']} | {' | '.join(twin)}"
    )


def main(argv: list[str] | None = None) -> int:
    """Write ``designs/3d/`` (or ``--check`` it)."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--check", action="store_true", help="walk the committed files again and compare")
    parser.add_argument("--tries", type=int, default=6, help="candidates walked per pick, at most (default 6)")
    parser.add_argument("--pictures", action="store_true", help="only draw the committed designs' pictures again")
    args = parser.parse_args(argv)
    FOLDER.mkdir(parents=True, exist_ok=True)
    if args.check:
        return _check()
    if args.pictures:
        for path in sorted(FOLDER.glob("*.toml")):
            print(draw(path), flush=True)
        return 0
    rows, tried, seen = [], [], {}
    for prefix, why, cells in candidates(load_map3d(MAP).cells):
        for cell in cells[: args.tries]:
            name = f"{prefix}_comb{cell.value:g}L_omega{cell.omega:g}"
            key = (cell.value, cell.omega)
            first = key not in seen
            if first:
                path = FOLDER / f"{name}.toml"
                map3d_design(cell.feet, cell.value, cell.omega).save(path, force=True)
                seen[key] = walk_both(path)
                print(f"{name}: {seen[key]}", flush=True)
                if not _agree(seen[key]):
                    path.unlink()
                    path.with_suffix(".png").unlink(missing_ok=True)
            if _agree(seen[key]):
                rows.append((name, why, cell, seen[key]))
                break
            if first:  # a cell both picks tried is listed once
                tried.append((cell, seen[key]))
    write_text_atomic(FOLDER / "README.md", readme(rows, tried))
    return 0 if len(rows) == 2 else 1


def _agree(row: dict) -> bool:
    """Both engines walk every step, within one step of each other and 5 % of the advance."""
    if row["outcome"] != "walks" or row.get("twin_outcome", "walks") != "walks":
        return False
    return abs(row["advance_m"] - row.get("twin_advance_m", row["advance_m"])) <= 0.05 * row["advance_m"]


def _check() -> int:
    """Walk the committed designs again; 0 when the README's rows come out the same."""
    text = (FOLDER / "README.md").read_text(encoding="utf-8")
    rows = json.loads(text.split("<!-- rows: ")[1].split(" -->")[0])
    same = True
    for name, row in rows.items():
        again = walk_both(FOLDER / f"{name}.toml", draw=False)
        print(f"{name}: {again}", flush=True)
        same &= again == row
    print("designs/3d/README.md " + ("matches" if same else "differs from") + " the walks")
    return 0 if same else 1


if __name__ == "__main__":
    raise SystemExit(main())
