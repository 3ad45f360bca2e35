"""Reading a log: numbers parsed fast, every bad cell named by row, line and column."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hdselect.base.errors import InputError
from hdselect.motion.logfile import read_log
from hdselect.robot.model import load_robot
from helpers.robots import write_chain

DEG = math.pi / 180


@pytest.fixture
def arm(tmp_path):
    """A revolute joint `turn` (+-170 deg) and a prismatic `slide` (+-1 m)."""
    path = write_chain(tmp_path, [("turn", "revolute", -170 * DEG, 170 * DEG),
                                  ("slide", "prismatic", -1.0, 1.0)])
    return load_robot(path)


def read(tmp_path, arm, text: str):
    path = tmp_path / "log.csv"
    path.write_bytes(text.encode("utf-8"))
    return read_log(path, arm, np.array([DEG, 1.0]), ["deg", "m"])


def refused(tmp_path, arm, text: str) -> InputError:
    with pytest.raises(InputError) as info:
        read(tmp_path, arm, text)
    assert info.value.path == tmp_path / "log.csv"
    return info.value


def test_columns_in_any_order_other_columns_ignored_blank_lines_skipped(tmp_path, arm):
    log = read(tmp_path, arm, "\ufeffnote, q_slide ,t,q_turn\n\nok,0.5,0,10\n\n"
                              "fine,0.25,0.1,20\r\nx,0,0.2,30\n")
    np.testing.assert_allclose(log.t, [0, 0.1, 0.2])
    np.testing.assert_allclose(log.q, [[10 * DEG, 0.5], [20 * DEG, 0.25], [30 * DEG, 0.0]])
    assert log.qd is None and log.qdd is None
    assert not log.q.flags.writeable and not log.t.flags.writeable


def test_quoted_numbers_are_read_too(tmp_path, arm):
    log = read(tmp_path, arm, 't,q_turn,q_slide\n"0","5",0\n1,"-5","0.5"\n')
    np.testing.assert_allclose(log.q, [[5 * DEG, 0.0], [-5 * DEG, 0.5]])


@pytest.mark.parametrize(("text", "field", "says"), [
    ("t,q_turn,q_slide,q_turn\n0,0,0,0\n1,1,1,1\n", "q_turn", "appears twice"),
    ("t,q_turn,q_slide\n0,0,0\n1,1\n", None, "data row 2 (line 3) has 2 cells, the header 3"),
    ("t,q_turn,q_slide\n0,0,0\n\n1,abc,0\n", "q_turn", "data row 2 (line 4): not a finite "
     "number: 'abc'"),
    ("t,q_turn,q_slide\n0,0,0\n1,1e400,0\n", "q_turn", "data row 2 (line 3): not a finite "
     "number: inf"),
    ("t,q_turn,q_slide\n0,0,0\n1,nan,0\n", "q_turn", "not a finite number: nan"),
    ("t,q_turn,q_slide\n0,0,0\n\n1,171,0\n", "q_turn", "data row 2 (line 4): 171 deg is outside "
     "the limits of joint 'turn' [-170, 170] deg"),
    ("t,q_turn,q_slide\n0,0,0\n1,0,1.5\n", "q_slide", "1.5 m is outside the limits of joint "
     "'slide' [-1, 1] m"),
    ("t,q_turn,q_slide,qd_turn,qd_slide\n0,0,0,0,0\n1,0,0,1e300,0\n", "qd_turn",
     "1e+300 is not a speed between"),
    ("t,q_turn,q_slide\n1e300,0,0\n2e300,0,0\n", "t", "is not a time between"),
    ("t,q_turn,q_slide\n0,0,0\n0,1,0\n", "t", "time must increase; data row 2 (line 3)"),
    ("t,q_turn,q_slide\n0,0,0\n", None, "at least two samples"),
    ("\n\n", None, "at least two samples"),
])
def test_a_bad_cell_is_named_by_row_line_and_column(tmp_path, arm, text, field, says):
    error = refused(tmp_path, arm, text)
    assert error.field == field and says in error.reason, error


def test_a_file_that_is_not_text_is_one_error(tmp_path, arm):
    path = tmp_path / "log.csv"
    path.write_bytes(b"t,q_turn,q_slide\n0,0,0\n\xff\xfe,1,1\n")
    with pytest.raises(InputError, match="cannot read CSV"):
        read_log(path, arm, np.array([DEG, 1.0]), ["deg", "m"])
