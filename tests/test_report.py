"""``report.md`` reads like a report: a summary of verdicts first, every figure linked with a caption,
every table column with its unit, the same text on every run, figures not clipped, legends true.

Each section runs with its default settings, except the simulation, which runs two scenarios for
one step (its Markdown is the same code). The contact/energy section is checked the same way in
``tests/test_energy.py``, the animation section in ``tests/test_viewer.py``.
"""

from __future__ import annotations

import itertools
import math
import re
import time
from pathlib import Path

import numpy as np
import pytest
from report_checks import assert_reads_like_a_report, columns_without_units, tables

from pasibot_pin.jobs import run_jobs
from pasibot_pin.report import markdown, model, torques
from pasibot_pin.report.simulation import SimulationPlan
from pasibot_pin.studies.simulation_study import SimulationStudySettings

SMALL_SIMULATION = SimulationStudySettings(
    scenarios=("quasi-static", "run4"), fast_steps=1, check_steps=1, static_samples=4
)


def _simulation(out: Path):
    plan = SimulationPlan(out, SMALL_SIMULATION)
    run_jobs(plan.jobs(), plan.done, 1)
    return plan


def test_the_checks_catch_what_they_look_for(tmp_path):
    assert columns_without_units("| x | K_e |\n|---|---|\n| a | 306.4 |\n| b | 13/60 |") == ["K_e"]
    assert columns_without_units("| x | K_e [N.m/rad] |\n|---|---|\n| a | 306.4 (R² 0.88) |") == []
    (tmp_path / "a.png").write_bytes(b"")
    with pytest.raises(AssertionError, match="not linked"):
        assert_reads_like_a_report(tmp_path, "![b](b.png)\n\n*a caption long enough to count*\n", 1)
    with pytest.raises(AssertionError, match="no caption"):
        assert_reads_like_a_report(tmp_path, "![a](a.png)\n\ntext\n", 1)


@pytest.mark.slow
@pytest.mark.integration
def test_kinematics_section(analyzed):
    """The kinematics section of the plain install's report: its figures linked and captioned, and the summary's
    rows quote the section's own table (the parallel leg's stroke, its band and its stance foot pitch)."""
    text = analyzed.section("Kinematics")
    assert_reads_like_a_report(analyzed.folder, text, 9, shared=True)
    header, rows = tables(text)[0]
    leg = {row[0]: dict(zip(header, row)) for row in rows}
    summary = analyzed.section("Summary")
    quoted = re.search(r"\| stroke ([\d.]+) L, off the line by at most ([\d.]+) L \|", summary)
    stroke, band = map(float, quoted.groups())
    assert stroke == pytest.approx(float(leg["parallel"]["stroke [L]"]), abs=5e-4)
    assert band == pytest.approx(float(leg["parallel"]["ankle band [L]"]), abs=5e-5)
    quoted = re.search(r"within ([\d.]+)° in stance; the rigid foot tilts up to ([\d.]+)°", summary)
    level, tilt = map(float, quoted.groups())
    assert level == pytest.approx(float(leg["parallel"]["stance foot pitch max [deg]"]), abs=6e-4)
    assert tilt == pytest.approx(float(leg["rigid"]["stance foot pitch max [deg]"]), abs=0.06)


@pytest.mark.slow
def test_torques_section_and_its_summary_rows(tmp_path):
    built = torques.build(tmp_path)
    assert_reads_like_a_report(tmp_path, built.markdown, 3)
    facts = built.facts
    summary = markdown.summary({"dynamics": facts})
    assert ", ".join(f"{v:.2f}" for v in facts["seed_preset"]) in summary
    assert ", ".join(f"{v:.0f}" for v in facts["seed_stored"]) in summary
    assert f"R² = {facts['run4_r2']:.2f}" in summary
    # the seed preset reproduces the stored values (the verdict 'reproduced' is earned)
    assert facts["seed_preset"] == pytest.approx(facts["seed_stored"], abs=0.006)


def test_report_order_summary_first():
    text = markdown.report_text(["## Model\n", "## Kinematics\n"], {})
    assert text.index("## Summary") < text.index("## Model") < text.index("## Kinematics")
    assert "| question | the seed claims | the model finds | verdict |" in text
    assert "## Answers" not in text


def test_the_answers_box_opens_the_report():
    from pasibot_pin.report.answers import WALKING_SLOT, answer_lines

    lines = answer_lines(
        ["- a walks.", "- b fell."], "- **What to build**: d.", "- **The motor**: m.", "- **The spring**: s."
    )
    text = markdown.report_text(["", "## Model\n"], {"answers": {"lines": lines}})
    assert text.index("# PASIBOT analysis") < text.index("## Answers") < text.index("## Summary")
    box = text.split("## Answers", 1)[1].split("## Summary", 1)[0]
    assert WALKING_SLOT in lines and WALKING_SLOT not in box  # the slot is marked in the README, not shown here
    assert "> - **Does it walk?**\n>   - a walks.\n>   - b fell.\n" in box
    assert box.count("> - **") == 4  # walking, what to build, motor, spring: one bullet each


def test_the_walking_section_comes_right_after_the_answers_box():
    from pasibot_pin.report.answers import answer_lines

    lines = answer_lines(["- a walks."], "- **What to build**: d.", "- **The motor**: m.", "- **The spring**: s.")
    text = markdown.report_text(["## Model\n"], {"answers": {"lines": lines}}, ["## Does it walk?\n"])
    assert text.index("## Answers") < text.index("## Does it walk?") < text.index("## Summary") < text.index("## Model")


@pytest.mark.slow
@pytest.mark.integration
def test_the_walking_section_draws_the_map_and_a_walker_that_walks(analyzed):
    """The section's files are in the report's folder (no link into docs/), and its animation is of a walk."""
    from PIL import Image

    from pasibot_pin.report.walking_section import MAP_PNG, WALK_GIF

    text = analyzed.section("Does it walk?")
    assert "docs/" not in text.replace("designs/", "")
    assert f"]({MAP_PNG})" in text and f"]({WALK_GIF})" in text and ": walks." in text
    assert_reads_like_a_report(analyzed.folder, text, 2, shared=True)
    with Image.open(analyzed.folder / WALK_GIF) as gif:
        assert gif.size[0] >= 640 and gif.n_frames > 10
    with Image.open(analyzed.folder / MAP_PNG) as png:
        assert png.size[0] > 600


@pytest.mark.slow
@pytest.mark.integration
def test_the_installed_report_reads_like_a_report(analyzed):
    """The whole report of the plain install: every figure in its folder linked from report.md and captioned,
    every numeric column with its unit, one resolution; one section per step of
    :data:`~pasibot_pin.cli.analyze.STEPS` and the summary, the walking section right after the answers box, before
    the summary."""
    from pasibot_pin.cli.analyze import STEPS

    assert_reads_like_a_report(analyzed.folder, analyzed.text, 40)
    headings = re.findall(r"^## (.+)$", analyzed.text, re.M)
    assert headings[:3] == ["Answers", "Does it walk?", "Summary"]
    assert len(headings) == len(STEPS) + 1  # every step's section and the summary (the answers step has its box)


def test_the_summary_says_how_runs_fell():
    assert markdown._runs_pitch(math.radians(41.3), [math.inf, math.inf]) == (
        "the largest hip pitch is 41.3° in run 1; runs 2 and 3 fell"
    )
    assert markdown._runs_pitch(math.inf, [math.radians(10.0)]) == "the largest hip pitch is 10.0° in run 2; run 1 fell"


def test_the_summary_with_every_section():
    facts = {
        "simulation": {
            "margin_run1": 4.8,
            "run1_fitted": math.radians(41.3),
            "run23_fitted": [math.inf, math.inf],
            "fall_min": 0.8,
            "fall_max": 3.2,
        },
        "contact_energy": {
            "run1_ok": 13,
            "run1_n": 60,
            "run1_cop": (-0.166, 0.229),
            "sole": (-0.025, 0.075),
            "motor_peak": 39.1,
            "motor_omega": 5.0,
            "motor_scenario": "run4",
            "flywheel": 11.95,
            "fluctuation": 0.05,
        },
    }
    text = markdown.summary(facts)
    assert "by only 4.8 N.m/rad" in text and "the largest hip pitch is 41.3° in run 1; runs 2 and 3 fell" in text
    assert "fell and fell" not in text
    assert "13 of 60 samples" in text and "-25 to +75 mm" in text and "-166 to +229 mm" in text
    assert "one motor can drive both cranks (run4, 5 rad/s)" in text
    assert "39.1" not in text and "12 kg.m²" not in text  # stated once, in the answers box
    assert "feasible" not in text  # a 12 kg.m² flywheel is no proof of feasibility
    assert text.count("\n| ") == 1 + 3  # header and three rows


@pytest.mark.slow
def test_model_and_simulation_sections_read_like_a_report_and_ignore_the_clock(tmp_path, monkeypatch):
    """Same text on a second run whose clock jumps by an hour at every reading: no wall-clock time in it."""

    def sections(out: Path) -> str:
        out.mkdir()
        plan = _simulation(out)
        return "\n".join([model.section(out), plan.markdown()]), plan

    first, plan = sections(tmp_path / "a")
    assert_reads_like_a_report(tmp_path / "a", first, 9)
    assert plan.facts() == {}, "run1 is not in the small study: no simulation row in the summary"

    import pasibot_pin.report.simulation as simulation_report

    anim_note = plan.anim_note  # the animation's meshcat server waits on the clock: keep its note
    monkeypatch.setattr(simulation_report, "write_check_animation", lambda out, name, base: anim_note)
    ticks = itertools.count()
    fake = lambda: 3600.0 * next(ticks)  # noqa: E731
    for name in ("perf_counter", "time", "monotonic", "process_time"):
        monkeypatch.setattr(time, name, fake)
    second, _ = sections(tmp_path / "b")
    assert first == second


# --------------------------------------------------------------------------- the figures
def _sticks_out(fig) -> bool:
    """Whether anything drawn (labels, titles, legends, tick labels) reaches beyond the figure's edges."""
    fig.canvas.draw()
    tight = fig.get_tightbbox(fig.canvas.get_renderer())  # [in], drawn artists only
    width, height = fig.get_size_inches()
    tol = 1.0 / fig.dpi
    return tight.x0 < -tol or tight.y0 < -tol or tight.x1 > width + tol or tight.y1 > height + tol


def _legend_without_drawing(fig) -> list[str]:
    """Legend entries whose line has no point drawn."""
    out = []
    for ax in fig.axes:
        legend = ax.get_legend()
        if legend is None:
            continue
        handles, labels = ax.get_legend_handles_labels()
        for handle, label in zip(handles, labels):
            data = handle.get_xydata() if hasattr(handle, "get_xydata") else np.ones((1, 2))
            if len(data) == 0 or not np.any(np.isfinite(data)):
                out.append(label)
    return out


def test_static_equilibrium_figure_is_not_clipped_and_lists_only_drawn_lines():
    import matplotlib.pyplot as plt

    from pasibot_pin.studies.methods.statics import StaticEquilibrium
    from pasibot_pin.viz.plots_simulation import plot_static_equilibrium

    theta = np.linspace(math.pi / 2, 3 * math.pi / 2, 5)

    def eq(stable: bool) -> StaticEquilibrium:
        n = len(theta)
        return StaticEquilibrium(
            theta=theta,
            hip_pitch=np.linspace(-0.1, 0.1, n),
            stiffness=np.full(n, 1.0 if stable else -1.0),
            found=np.ones(n, bool),
        )

    fig = plot_static_equilibrium({"fitted": eq(False), "twice K_e": eq(True)})
    try:
        assert not _sticks_out(fig)
        assert _legend_without_drawing(fig) == []
        assert fig.axes[0].get_legend_handles_labels()[1] == ["twice K_e"]
        assert "fitted" in fig.axes[0].get_title()
    finally:
        plt.close(fig)


def test_cost_of_transport_figure_is_not_clipped():
    import matplotlib.pyplot as plt

    from pasibot_pin.studies.energy import omega_table
    from pasibot_pin.viz.plots_contact import plot_cost_of_transport

    fig = plot_cost_of_transport(omega_table((0.1, 1.0), 16.0, 0.0, 8, ("spring",)))
    try:
        assert not _sticks_out(fig)
        assert _legend_without_drawing(fig) == []
    finally:
        plt.close(fig)


def test_save_figure_file_writes_the_pixels_savefig_writes(tmp_path):
    import matplotlib as mpl
    import matplotlib.pyplot as plt
    from PIL import Image

    from pasibot_pin.report.files import save_figure_file
    from pasibot_pin.viz.figure_files import TEXT_HINTING
    from pasibot_pin.viz.plots_layout import subplots

    for transparent in (False, True):
        fig, ax = subplots(figsize=(4, 3))
        ax.plot([0.0, 1.0, 2.0], [1.0, -1.0, 0.5], label="a line")
        ax.set_title("title")
        ax.legend()
        if transparent:
            fig.patch.set_alpha(0.0)
        try:
            save_figure_file(fig, tmp_path / "ours.png", dpi=72)
            with mpl.rc_context({"text.hinting": TEXT_HINTING}):  # the text drawn as save_figure_file draws it
                fig.savefig(tmp_path / "theirs.png", dpi=72)  # laid out the same (the engine is idempotent)
        finally:
            plt.close(fig)
        ours, theirs = Image.open(tmp_path / "ours.png"), Image.open(tmp_path / "theirs.png")
        assert ours.size == theirs.size == (4 * 72, 3 * 72)
        assert round(ours.info["dpi"][0]) == 72
        assert np.array_equal(np.asarray(ours.convert("RGBA")), np.asarray(theirs.convert("RGBA")))
        assert (ours.mode == "RGBA") == transparent


def test_margin_layout_keeps_every_text_inside_and_the_panels_apart():
    import matplotlib.pyplot as plt

    from pasibot_pin.viz.plots_layout import subplots

    fig, axes = subplots(2, 2, figsize=(8, 6))
    x = np.linspace(0.0, 1.0, 50)
    axes[0, 0].plot(x, 1e-14 * x, label="tiny")
    axes[0, 0].set_title("an offset text above the axes and a title")
    axes[0, 1].set_xticks([0, 1, 2], ["a long\nlabel", "another long label", "c"], rotation=90)
    axes[0, 1].set_xlabel("rotated tick labels [-]")
    mesh = axes[1, 0].pcolormesh(np.arange(12.0).reshape(3, 4))
    fig.colorbar(mesh, ax=axes[1, 0], label="a colour bar's label [unit]")
    axes[1, 1].plot(x, 1000.0 * x, label="left")
    twin = axes[1, 1].twinx()
    twin.plot(x, -x, color="r", label="right")
    twin.set_ylabel("the twin's label [unit]")
    axes[1, 1].legend(loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2)
    for ax in axes.flat:
        ax.set_ylabel("a y label [unit]")
    fig.suptitle("a suptitle")
    try:
        assert not _sticks_out(fig)
        renderer = fig.canvas.get_renderer()
        boxes = [(ax.get_subplotspec().get_topmost_subplotspec(), ax.get_tightbbox(renderer)) for ax in fig.axes]
        for i, (cell_a, a) in enumerate(boxes):
            for cell_b, b in boxes[i + 1 :]:
                if cell_a != cell_b:  # twins and colour bars share their parent's cell
                    assert not a.overlaps(b), (cell_a, cell_b)
    finally:
        plt.close(fig)


def _floor_study(duration: float = 2.0):
    from types import SimpleNamespace

    def row(case, weld, fell, floor, failed=False):
        return SimpleNamespace(
            scenario="run1",
            case=case,
            weld_max_pitch=math.radians(weld),
            weld_fell_at=fell,
            floor_max_pitch=math.radians(floor),
            floor_failed=failed,
        )

    rows = [row("fitted", 19.9, math.nan, 2.9), row("no spring", 61.2, 0.8, 0.0), row("half K_e", 60.3, 1.19, 2.7)]
    return SimpleNamespace(rows=rows, settings=SimpleNamespace(duration=duration))


def test_floor_springs_figure_has_a_legend_readable_ticks_and_a_visible_zero():
    import matplotlib.pyplot as plt

    from pasibot_pin.viz.plots_floor import plot_weld_vs_floor

    fig = plot_weld_vs_floor(_floor_study())
    try:
        ax = fig.axes[0]
        assert not _sticks_out(fig)
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        assert labels == ["welded stance foot", "on the floor (heel and toe)", "fell or failed (bar: where it stopped)"]
        ticks = ax.get_xticklabels()
        assert [t.get_text() for t in ticks] == ["fitted", "no spring", "half K_e"]
        assert all(t.get_fontsize() >= 8 and t.get_rotation() == 0 for t in ticks)
        values = [t.get_text() for t in ax.texts]  # one label per bar: its value, or how it ended
        assert values == ["19.9", "2.9", "fell", "0.0", "fell", "2.7"]
        zero_marks = [ln for ln in ax.lines if list(ln.get_ydata()) == [0.0] and ln.get_marker() == "o"]
        assert len(zero_marks) == 6  # a dot on the axis under every bar: a zero bar is not a gap
    finally:
        plt.close(fig)


def _walk(t_end: float, fell: bool, dt: float = 0.05):
    from types import SimpleNamespace

    t = np.arange(0.0, t_end + 1e-9, dt)
    pitch = np.radians(60.5) * (t / t_end) ** 2 if fell else 0.3 * np.sin(t)
    n = len(t)
    return SimpleNamespace(
        t=t, hip_pitch=pitch, fell=fell, impacts=[], beta=np.full((n, 2), 1.3), motor_torque=np.zeros((n, 2))
    )


def test_simulation_figure_shows_early_falls_on_their_own_time_axis():
    """Falls at 0.8 and 1.2 s of a 63 s walk: a panel of the first 1.8 s holds them (x at each fall, its time
    written), the whole-run panels (shared axis up to 63 s) only the springs that held."""
    import matplotlib.pyplot as plt

    from pasibot_pin.viz.plots_simulation import fall_window, plot_simulation

    runs = {"fitted": _walk(62.8, False), "no spring": _walk(0.8, True), "half K_e": _walk(1.2, True)}
    assert fall_window(runs) == pytest.approx(1.8)
    fig = plot_simulation(runs, main="fitted", rest_angle=1.3)
    try:
        assert not _sticks_out(fig)
        first, whole, *rest = fig.axes
        assert first.get_xlim() == pytest.approx((0.0, 1.8))
        assert first.get_legend_handles_labels()[1] == ["fitted", "no spring", "half K_e"]
        falls = [ln for ln in first.lines if ln.get_marker() == "x"]
        assert sorted(float(ln.get_xdata()[0]) for ln in falls) == pytest.approx([0.8, 1.2])
        assert sorted(t.get_text() for t in first.texts) == ["fell at 0.80 s", "fell at 1.20 s"]
        assert max(np.max(ln.get_xdata()) for ln in first.lines if ln.get_label() == "fitted") <= 1.8
        assert whole.get_legend_handles_labels()[1] == ["fitted"]
        assert whole.get_xlim()[1] >= 62.8 and all(ax.get_xlim() == whole.get_xlim() for ax in rest)
    finally:
        plt.close(fig)
    # no early fall: three panels, every run in the first
    fig = plot_simulation({"fitted": _walk(62.8, False), "twice K_e": _walk(62.8, False)})
    try:
        assert len(fig.axes) == 3 and fig.axes[0].get_legend_handles_labels()[1] == ["fitted", "twice K_e"]
    finally:
        plt.close(fig)


def test_robot_figure_names_every_symbol():
    import matplotlib.pyplot as plt

    from pasibot_pin.model.robot import load
    from pasibot_pin.viz.plots import GROUP_LABELS, plot_robot

    fig = plot_robot(load("spring", 2), legend=True)
    try:
        assert not _sticks_out(fig)
        labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
        for group in ("hoeken", "pantograph", "foot"):
            assert GROUP_LABELS[group] in labels
        assert GROUP_LABELS["extension"] not in labels  # the spring variant has none
        assert "fixed pivots on the hip (crank j0, j3, j8)" in labels and "hip frame (body origin)" in labels
        assert "ground z = 0" in labels
    finally:
        plt.close(fig)
