"""A linkage that cannot assemble is an :class:`AssemblyError` naming the design fields a user can
change (K and the link ratios, in L), not internal lengths (issue 34)."""

from __future__ import annotations

import re

import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.errors import AssemblyError, DesignError
from pasibot_pin.model.assembly import check_full_turn
from pasibot_pin.model.design import Design
from pasibot_pin.model.params import Geometry


@pytest.mark.parametrize(("change", "field"), [({"K": 1.2}, "K"), ({"r9": 3.0}, "r9")])
def test_a_loop_that_cannot_close_names_the_fields_to_change(change, field):
    with pytest.raises(AssemblyError) as caught:
        check_full_turn(Geometry().with_(**change), "parallel")
    err = caught.value
    assert isinstance(err, DesignError)
    assert field in err.fields and set(err.fields) <= {"K", *(f"r{k}" for k in range(1, 14))}
    assert re.search(rf"\b{field}\b", str(err)) and "[ratios], in L" in str(err)
    assert not re.search(r"\bL\d+ =", str(err))  # no internal length names (L8 = ...)


def test_walk_refuses_such_a_design_file_in_one_line_naming_k(tmp_path, capsys):
    path = Design(variant="parallel", K=1.2).save(tmp_path / "bad.toml")
    code = main(["walk", "--design", str(path), "--steps", "3"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "Traceback" not in err and len(err.splitlines()) == 1, err
    assert "cannot make a full turn" in err and re.search(r"change K, ", err), err
