"""`pasibot find-walker`: from a crank speed to a design file that `pasibot walk` confirms; bad input is one
line before any work; a search that finds nothing writes nothing (issue 34)."""

from __future__ import annotations

import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.explore.find_walker import FAILED, WalkerSearch, find_walker
from pasibot_pin.explore.plan import Range
from pasibot_pin.model.design import load_design
from pasibot_pin.studies.walking import WalkSettings, walk_design

pytest.importorskip("optuna")


@pytest.mark.slow
def test_a_search_writes_a_walker_that_walk_confirms(tmp_path, capsys):
    out = tmp_path / "new" / "w.toml"  # a folder not there yet: made when the walker is written
    argv = ["find-walker", "--omega", "2", "--budget", "4", "--steps", "3", "--out", str(out), "--no-progress",
            "--vary", "parallel_toe=4:8", "--vary", "parallel_heel=4:8"]  # fmt: skip
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert " of 4 candidates walk 3 steps at 2 rad/s" in text and out.is_file()
    design = load_design(out)
    assert design.omega == 2.0 and 4 <= design.parallel_toe <= 8 and 4 <= design.parallel_heel <= 8
    assert walk_design(design, WalkSettings(steps=3)).verdict.walks  # confirmed by the walk itself
    assert main(argv) == 2 and "exists" in capsys.readouterr().err  # never over a file without --force


@pytest.mark.slow
def test_scores_rank_walkers_first_and_by_the_objective():
    search = WalkerSearch(2.0, "sole", budget=3, steps=3,
                          ranges=(Range("parallel_toe", 4.0, 8.0), Range("parallel_heel", 4.0, 8.0)))  # fmt: skip
    result = find_walker(search, workers=1, progress=False)
    assert len(result.candidates) == 3
    for c in result.candidates:
        sole = c.values["parallel_toe"] + c.values["parallel_heel"]
        assert c.score == pytest.approx(sole) if c.walks else c.score == FAILED - c.steps
    if result.walkers:
        assert result.best() == search.design(result.walkers[0].values)


@pytest.mark.slow
def test_nothing_walks_nothing_written(tmp_path, capsys):
    out = tmp_path / "new" / "w.toml"  # nor its folder
    argv = ["find-walker", "--omega", "3", "--budget", "2", "--steps", "3", "--out", str(out), "--no-progress",
            "--vary", "parallel_toe=0.5:0.8", "--vary", "parallel_heel=0.5:0.8"]  # fmt: skip
    assert main(argv) == 1
    assert "no walker found in 2 candidates: nothing written" in capsys.readouterr().out
    assert not out.exists() and not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["--omega", "25"], "--omega"),
        (["--omega", "2", "--budget", "0"], "--budget"),
        (["--omega", "2", "--budget", "20000"], "--budget"),
        (["--omega", "2", "--objective", "speed"], "--objective"),
        (["--omega", "0.05", "--budget", "10000", "--steps", "1000"], "past the limit"),
        (["--omega", "2", "--steps", "2"], "--steps"),
        (["--omega", "2", "--vary", "variant=rigid,spring"], "--vary"),
    ],
)
def test_bad_input_is_one_line_before_any_work(argv, fragment, tmp_path, capsys):
    out = tmp_path / "w.toml"
    assert main(["find-walker", *argv, "--out", str(out), "--no-progress"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and fragment in err[0] and "Traceback" not in err[0]
    assert not out.exists()


def test_an_unwritable_out_is_refused_before_any_work(tmp_path, capsys):
    assert main(["find-walker", "--omega", "2", "--out", str(tmp_path), "--no-progress"]) == 2
    assert "--out" in capsys.readouterr().err
    assert main(["find-walker", "--omega", "2", "--out", "/proc/x/w.toml", "--no-progress"]) == 2


@pytest.mark.slow
def test_a_3d_search_writes_an_upright_walker_that_walk_3d_confirms(tmp_path, capsys):
    """``--3d``: the candidates walk on the 3-D floor from the comb-soled base; the written design keeps the comb."""
    from pasibot_pin.studies.walking import walk_design_3d
    from pasibot_pin.studies.walking_map3d import recommended_walker

    out = tmp_path / "w3.toml"
    argv = ["find-walker", "--3d", "--omega", "2", "--budget", "2", "--steps", "3", "--out", str(out),
            "--no-progress", "--workers", "1"]  # fmt: skip
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert " of 2 candidates walk 3 steps in 3-D at 2 rad/s" in text and "--3d" in text
    design = load_design(out)
    comb = recommended_walker()
    assert (design.sole_inner, design.sole_gap_from, design.sole_gap_to) == (
        comb.sole_inner,
        comb.sole_gap_from,
        comb.sole_gap_to,
    )
    walk = walk_design_3d(design, WalkSettings(steps=3))
    assert walk.verdict.walks and walk.result.max_hip_roll_deg < 10.0  # upright, confirmed by its own walk


def test_a_3d_candidate_whose_legs_meet_is_collided_not_a_crash():
    """A sole reaching into the other leg: ``collided`` before any walk, scored as failed."""
    from pasibot_pin.explore.find_walker import walk_candidate
    from pasibot_pin.model.design import Design

    base = Design(variant="parallel").to_dict()
    outcome, steps, score, detail = walk_candidate(base, 2.0, {"sole_inner": 3.9}, 3, "sole", spatial=True)
    assert (outcome, steps, score) == ("collided", 0, FAILED) and "sole_inner" in detail
    outcome, _, score, detail = walk_candidate(base, 2.0, {"sole_gap_from": 0.3, "sole_gap_to": 0.2}, 3, "sole", True)
    assert (outcome, score) == ("refused", FAILED) and "sole_gap_from" in detail


def _uneven_walk(base, omega, values, steps, objective, spatial=False):
    """A stand-in for a walk whose length varies from candidate to candidate (so two workers finish out of order)."""
    import time

    toe, heel = values["parallel_toe"], values["parallel_heel"]
    time.sleep(0.002 + 0.03 * ((toe * 7.0 + heel * 13.0) % 1.0))
    score = (toe - 6.0) ** 2 + (heel - 4.0) ** 2
    return ("walks", steps, score, "") if score < 4.0 else ("slipped", 1, FAILED - 1, "")


def _trace(result):
    return [(c.number, c.outcome, c.score, tuple(sorted(c.values.items()))) for c in result.candidates]


@pytest.mark.slow
def test_the_same_seed_gives_the_same_candidates_on_one_worker_or_two(monkeypatch):
    """Past TPE's 10 random start-up candidates each ask depends on what was told: told in trial order, the
    candidates are the same however the workers' walks interleave (runs of uneven length, finishing out of order)."""
    import pasibot_pin.explore.find_walker as fw

    monkeypatch.setattr(fw, "walk_candidate", _uneven_walk)
    search = WalkerSearch(2.0, "sole", budget=24, steps=3, seed=7)
    one = find_walker(search, workers=1, progress=False)
    two = [find_walker(search, workers=2, progress=False) for _ in range(2)]
    assert [c.number for c in one.candidates] == list(range(24))
    assert _trace(two[0]) == _trace(one) and _trace(two[1]) == _trace(one)
    other = find_walker(WalkerSearch(2.0, "sole", budget=24, steps=3, seed=8), workers=2, progress=False)
    assert _trace(other) != _trace(one)  # the seed does decide the candidates


@pytest.mark.slow
def test_find_walker_twice_with_one_seed_writes_the_same_file(tmp_path, capsys):
    """The command itself, run twice on two workers with real walks: the same count and the same design file."""
    outputs = []
    for name in ("a.toml", "b.toml"):
        out = tmp_path / name
        argv = ["find-walker", "--omega", "4", "--budget", "12", "--steps", "3", "--out", str(out), "--no-progress",
                "--workers", "2", "--seed", "3"]  # fmt: skip
        assert main(argv) in (0, 1)
        text = capsys.readouterr().out
        outputs.append((text.split(" candidates walk")[0], out.read_bytes() if out.exists() else None))
    assert outputs[0] == outputs[1]


def test_the_help_quotes_the_candidates_asked_ahead(capsys):
    from pasibot_pin.explore.find_walker import IN_FLIGHT

    with pytest.raises(SystemExit):
        main(["find-walker", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert f"asks {IN_FLIGHT} candidates ahead, so more than {IN_FLIGHT} add nothing" in text
    assert "the same seed gives the same candidates and file on any --workers" in text
